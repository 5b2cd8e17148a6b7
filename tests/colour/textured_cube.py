#!/usr/bin/python3
"""tests/colour/textured_cube.py DIR [--tile none] [--uv-scale S] - one textured part written two
ways, by Python (zipfile, Pillow), not by hovox (issue 29 checks): a 10 mm cube whose six faces each
map the whole of one 8 x 8 PNG (a colour ramp: red rising along u, green along v, blue 0.6) as
DIR/cube.3mf (a 3MF texture2d group, tile styles wrap unless --tile) and DIR/cube.obj + cube.mtl +
skin.png (OBJ vt coordinates, MTL map_Kd). --uv-scale multiplies the coordinates (1.5 puts UVs
outside [0, 1])."""
import io
import os
import sys
import zipfile

from PIL import Image

# the cube's corners and its faces (outward, counter-clockwise), each as two triangles
V = [(x, y, z) for z in (0, 10) for y in (0, 10) for x in (0, 10)]
QUADS = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
UV = [(0, 0), (1, 0), (1, 1), (0, 1)]


def texture():
    im = Image.new("RGB", (8, 8))
    im.putdata([(int(255 * x / 7), int(255 * (7 - y) / 7), 153) for y in range(8) for x in range(8)])
    buf = io.BytesIO()
    im.save(buf, "PNG")
    return buf.getvalue()


def triangles():
    for q in QUADS:
        yield (q[0], q[1], q[2]), (UV[0], UV[1], UV[2])
        yield (q[0], q[2], q[3]), (UV[0], UV[2], UV[3])


def write_3mf(path, png, tile, scale):
    coords, tris = [], []
    for t, uv in triangles():
        p = []
        for c in uv:
            p.append(len(coords))
            coords.append(c)
        tris.append('<triangle v1="%d" v2="%d" v3="%d" pid="3" p1="%d" p2="%d" p3="%d"/>' % (t + tuple(p)))
    model = ('<?xml version="1.0" encoding="UTF-8"?>\n<model unit="millimeter" xml:lang="en-US" '
             'xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02" '
             'xmlns:m="http://schemas.microsoft.com/3dmanufacturing/material/2015/02"><resources>'
             '<m:texture2d id="2" path="/3D/Textures/skin.png" contenttype="image/png" tilestyleu="%s" '
             'tilestylev="%s"/><m:texture2dgroup id="3" texid="2">%s</m:texture2dgroup>'
             '<object id="1" name="cube" type="model" pid="3" pindex="0"><mesh><vertices>%s</vertices>'
             '<triangles>%s</triangles></mesh></object></resources><build><item objectid="1"/></build></model>\n') % (
        tile, tile, "".join('<m:tex2coord u="%g" v="%g"/>' % (u * scale, v * scale) for u, v in coords),
        "".join('<vertex x="%g" y="%g" z="%g"/>' % p for p in V), "".join(tris))
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("[Content_Types].xml", '<?xml version="1.0" encoding="UTF-8"?>\n<Types xmlns="http://schemas.'
                   'openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="application/'
                   'vnd.openxmlformats-package.relationships+xml"/><Default Extension="model" ContentType="application/'
                   'vnd.ms-package.3dmanufacturing-3dmodel+xml"/><Default Extension="png" ContentType="image/png"/>'
                   '</Types>\n')
        z.writestr("_rels/.rels", '<?xml version="1.0" encoding="UTF-8"?>\n<Relationships xmlns="http://schemas.'
                   'openxmlformats.org/package/2006/relationships"><Relationship Target="/3D/3dmodel.model" Id="rel0" '
                   'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>\n')
        z.writestr("3D/_rels/3dmodel.model.rels", '<?xml version="1.0" encoding="UTF-8"?>\n<Relationships xmlns='
                   '"http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Target="/3D/Textures/'
                   'skin.png" Id="rel1" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dtexture"/>'
                   '</Relationships>\n')
        z.writestr("3D/3dmodel.model", model)
        z.writestr("3D/Textures/skin.png", png)


def write_obj(d, png, scale):
    with open(os.path.join(d, "skin.png"), "wb") as f:
        f.write(png)
    with open(os.path.join(d, "cube.mtl"), "w") as f:
        f.write("newmtl skin\nmap_Kd skin.png\n")
    with open(os.path.join(d, "cube.obj"), "w") as f:
        f.write("mtllib cube.mtl\no cube\n")
        for p in V:
            f.write("v %g %g %g\n" % p)
        for u, v in UV:
            f.write("vt %g %g\n" % (u * scale, v * scale))
        f.write("usemtl skin\n")
        for t, uv in triangles():
            f.write("f %s\n" % " ".join("%d/%d" % (i + 1, UV.index(c) + 1) for i, c in zip(t, uv)))


def main():
    d = sys.argv[1]
    tile = sys.argv[sys.argv.index("--tile") + 1] if "--tile" in sys.argv else "wrap"
    scale = float(sys.argv[sys.argv.index("--uv-scale") + 1]) if "--uv-scale" in sys.argv else 1.0
    os.makedirs(d, exist_ok=True)
    png = texture()
    write_3mf(os.path.join(d, "cube.3mf"), png, tile, scale)
    write_obj(d, png, scale)


if __name__ == "__main__":
    main()
