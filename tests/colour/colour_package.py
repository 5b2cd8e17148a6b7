#!/usr/bin/python3
"""tests/colour/colour_package.py - a colour printer's 3MF package, written by Python (zipfile and
Pillow, not hovox), and its independent check (issue 29 item 3):
  write DIR    DIR/turned.3mf: a 20 x 16 x 12 mm box (mm units) whose <v:volumedata> holds a
               <v:color> and no <v:composite>: a 5 x 4 x 3 RGB stack of 8 bits, filter linear, tile
               styles wrap, mirror, clamp, through a transform turned 30 degrees about z, scaled and
               moved (not axis-aligned); DIR/nearest.3mf the same with filter nearest
  check FILE.json [--icc FILE] [--intent NAME]
               FILE.json: {"package": ..., "voxels": [[x, y, z, r, g, b, f0 .. f5], ...]} (centres in
               mm, the colour hovox holds as sRGB in [0, 1], the six fractions). Each colour must be the
               spec's sampling (2.2: tile styles, filter, V counted from the bottom row; 5.2.1: linear
               sRGB) of the stack at the centre, written out again here, within 2e-6; each voxel's
               fractions Pillow ImageCms's CMYK of that colour (as 8 bits) through the profile, mixed
               by hovox/colour.h's rule (check_littlecms.mix), within 0.01."""
import json
import math
import os
import sys
import zipfile

from PIL import Image, ImageCms

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_littlecms import INTENTS, mix  # noqa: E402

N = (5, 4, 3)  # columns, rows, sheets
TILES = ("wrap", "mirror", "clamp")
A = math.radians(30)
S = (1 / 14.0, 1 / 11.0, 1 / 9.0)
# object (mm) -> UVW, ST_Matrix3D row-vector order: u = x m00 + y m10 + z m20 + m30 ...
T = (S[0] * math.cos(A), -S[1] * math.sin(A), 0,
     S[0] * math.sin(A), S[1] * math.cos(A), 0,
     0, 0, S[2],
     -0.35, 0.2, 0.05)


def texel(col, row, sheet):
    """The RGB of a texel (row counted from the top), 8 bits."""
    return ((37 * col + 91 * row + 53 * sheet + 11) % 256, (71 * col + 13 * row + 29 * sheet + 200) % 256,
            (17 * col + 57 * row + 101 * sheet + 90) % 256)


def tile_coord(s, style):
    if style == "wrap":
        return s - math.floor(s)
    if style == "mirror":
        return 1 - abs(s - 2 * math.floor(s / 2) - 1)
    return min(1.0, max(0.0, s))


def tap(i, n, style):
    if style == "wrap":
        return i % n
    if style == "mirror":
        return -1 - i if i < 0 else 2 * n - 1 - i if i >= n else i
    return min(n - 1, max(0, i))


def sample(x, nearest):
    """The stack's linear RGB in [0, 1] at object point x (mm)."""
    uvw = [x[0] * T[b] + x[1] * T[3 + b] + x[2] * T[6 + b] + T[9 + b] for b in range(3)]
    p = [tile_coord(uvw[b], TILES[b]) * N[b] - 0.5 for b in range(3)]
    if nearest:
        i = [tap(math.ceil(p[b] - 0.5), N[b], TILES[b]) for b in range(3)]
        return [c / 255.0 for c in texel(i[0], N[1] - 1 - i[1], i[2])]
    acc = [0.0, 0.0, 0.0]
    for d in range(8):
        w, i = 1.0, []
        for b in range(3):
            up = (d >> b) & 1
            f = p[b] - math.floor(p[b])
            w *= f if up else 1 - f
            i.append(tap(math.floor(p[b]) + up, N[b], TILES[b]))
        t = texel(i[0], N[1] - 1 - i[1], i[2])
        for c in range(3):
            acc[c] += w * t[c] / 255.0
    return acc


def srgb(c):
    c = min(1.0, max(0.0, c))
    return c * 12.92 if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055


CORE = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"
VOL = "http://schemas.3mf.io/3dmanufacturing/volumetric/2022/01"
QUADS = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
TYPES = ('<?xml version="1.0" encoding="UTF-8"?>\n<Types xmlns="http://schemas.openxmlformats.org/package/2006/'
         'content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.'
         'relationships+xml"/><Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-'
         '3dmodel+xml"/><Default Extension="png" ContentType="image/png"/></Types>\n')
RELS = ('<?xml version="1.0" encoding="UTF-8"?>\n<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/'
        'relationships"><Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/'
        '3dmanufacturing/2013/01/3dmodel"/></Relationships>\n')


def model(nearest):
    lo, hi = (4.0, 3.0, 1.0), (24.0, 19.0, 13.0)
    verts = [(hi[0] if c & 1 else lo[0], hi[1] if c & 2 else lo[1], hi[2] if c & 4 else lo[2]) for c in range(8)]
    tris = [t for q in QUADS for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    sheets = "".join('    <v:imagesheet path="/3D/colour/s%d.png"/>\n' % k for k in range(N[2]))
    return ('<?xml version="1.0" encoding="UTF-8"?>\n'
            '<model unit="millimeter" xmlns="%s" xmlns:v="%s" requiredextensions="v">\n <resources>\n'
            '  <v:image3d id="1">\n   <v:imagestack rowcount="%d" columncount="%d" sheetcount="%d">\n%s'
            '   </v:imagestack>\n  </v:image3d>\n'
            '  <v:functionfromimage3d id="2" image3did="1" filter="%s" tilestyleu="%s" tilestylev="%s" tilestylew="%s"/>\n'
            '  <v:volumedata id="3">\n   <v:color functionid="2" channel="color" transform="%s"/>\n  </v:volumedata>\n'
            '  <object id="4" type="model">\n   <mesh v:volumeid="3">\n    <vertices>\n%s    </vertices>\n'
            '    <triangles>\n%s    </triangles>\n   </mesh>\n  </object>\n </resources>\n'
            ' <build>\n  <item objectid="4"/>\n </build>\n</model>\n') % (
        CORE, VOL, N[1], N[0], N[2], sheets, "nearest" if nearest else "linear", TILES[0], TILES[1], TILES[2],
        " ".join(repr(v) for v in T), "".join('     <vertex x="%g" y="%g" z="%g"/>\n' % v for v in verts),
        "".join('     <triangle v1="%d" v2="%d" v3="%d"/>\n' % t for t in tris))


def write(out):
    os.makedirs(out, exist_ok=True)
    pngs = []
    for k in range(N[2]):
        im = Image.new("RGB", (N[0], N[1]))
        im.putdata([texel(col, row, k) for row in range(N[1]) for col in range(N[0])])
        path = os.path.join(out, "s%d.png" % k)
        im.save(path)
        pngs.append(open(path, "rb").read())
        os.remove(path)
    for name, nearest in (("turned.3mf", False), ("nearest.3mf", True)):
        with zipfile.ZipFile(os.path.join(out, name), "w", zipfile.ZIP_DEFLATED) as z:
            z.writestr("[Content_Types].xml", TYPES)
            z.writestr("_rels/.rels", RELS)
            z.writestr("3D/3dmodel.model", model(nearest))
            for k, data in enumerate(pngs):
                z.writestr("3D/colour/s%d.png" % k, data)


def check(path, extra):
    doc = json.load(open(path))
    icc = "/usr/share/color/icc/ghostscript/default_cmyk.icc"
    intent = "perceptual"
    for i, a in enumerate(extra):
        if a == "--icc":
            icc = extra[i + 1]
        if a == "--intent":
            intent = extra[i + 1]
    nearest = doc["package"].endswith("nearest.3mf")
    vox = doc["voxels"]
    worst_c = 0.0
    want_rgb = []
    for v in vox:
        want = [srgb(c) for c in sample(v[:3], nearest)]
        worst_c = max(worst_c, max(abs(a - b) for a, b in zip(want, v[3:6])))
        want_rgb.append(tuple(int(round(c * 255)) for c in v[3:6]))
    tr = ImageCms.buildTransform(ImageCms.createProfile("sRGB"), ImageCms.getOpenProfile(icc), "RGB", "CMYK",
                                 renderingIntent=INTENTS[intent])
    im = Image.new("RGB", (len(vox), 1))
    im.putdata(want_rgb)
    out = Image.new("CMYK", im.size)
    tr.transform.apply(im.im.id, out.im.id)
    worst_f = 0.0
    for v, k in zip(vox, out.getdata()):
        worst_f = max(worst_f, max(abs(a - b) for a, b in zip(mix(k, 1.0), v[6:12])))
    distinct = len(set(want_rgb))
    if worst_c > 2e-6 or worst_f > 0.01 or distinct < 20:
        sys.exit("%s: colours %.3g from the spec's sampling (> 2e-6?), fractions %.4f from Pillow ImageCms (> 0.01?), "
                 "%d distinct colours" % (doc["package"], worst_c, worst_f, distinct))
    print("%d voxels, %d colours: the spec's sampling within 2e-6, Pillow ImageCms (%s, %s) within 0.01"
          % (len(vox), distinct, os.path.basename(icc), intent))


if __name__ == "__main__":
    if sys.argv[1] == "write":
        write(sys.argv[2])
    else:
        check(sys.argv[2], sys.argv[3:])
