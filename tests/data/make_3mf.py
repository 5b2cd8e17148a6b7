#!/usr/bin/python3
# tests/data/make_3mf.py - 3MF Volumetric packages for the CLI tests, written with Python's zipfile and
# zlib only (an independent producer, not hovox's writer):
#   good/volumetric_box.3mf         a 4 x 3 x 2 mm box of 1 mm voxels at (10, 20, 0), materials "Vero
#                                   Cyan" and "Agilus" in the grey sheets of two 8-bit stacks, Agilus
#                                   rising along x: 0, 1/3, 2/3, 1 by column
#   bad/3mf_truncated.3mf           that package cut after half of its bytes
#   bad/3mf_no_model.3mf            without its model part 3D/3dmodel.model
#   bad/3mf_missing_image.3mf       without the sheet /3D/volumetric/agilus/sheet0002.png
#   bad/3mf_bad_dimensions.3mf      its stacks say 4 rows, the sheets have 3
# Run from the repository root: /usr/bin/python3 tests/data/make_3mf.py
import struct
import zipfile
import zlib

CORE = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"
VOL = "http://schemas.3mf.io/3dmanufacturing/volumetric/2022/01"
COLS, ROWS, SHEETS = 4, 3, 2


def png_grey(rows):
    """An 8-bit grey PNG from a list of rows of values."""
    def chunk(kind, data):
        c = kind + data
        return struct.pack(">I", len(data)) + c + struct.pack(">I", zlib.crc32(c) & 0xffffffff)
    raw = b"".join(b"\0" + bytes(r) for r in rows)
    ihdr = struct.pack(">IIBBBBB", len(rows[0]), len(rows), 8, 0, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def sheet(material):
    """Agilus = column / 3, Vero Cyan = 1 - that; every row alike."""
    vals = [round(255 * c / 3) for c in range(COLS)]
    if material == "cyan":
        vals = [255 - v for v in vals]
    return png_grey([vals] * ROWS)


def box_mesh():
    lo, hi = (10.0, 20.0, 0.0), (14.0, 23.0, 2.0)
    verts = [(hi[0] if c & 1 else lo[0], hi[1] if c & 2 else lo[1], hi[2] if c & 4 else lo[2]) for c in range(8)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = [t for q in quads for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    v = "".join('     <vertex x="%g" y="%g" z="%g"/>\n' % p for p in verts)
    t = "".join('     <triangle v1="%d" v2="%d" v3="%d"/>\n' % p for p in tris)
    return v, t


def model(rows=ROWS):
    v, t = box_mesh()
    stacks = ""
    for i, name in enumerate(("cyan", "agilus")):
        sheets = "".join('    <v:imagesheet path="/3D/volumetric/%s/sheet%04d.png"/>\n' % (name, k + 1) for k in range(SHEETS))
        stacks += ('  <v:image3d id="%d" name="%s">\n   <v:imagestack rowcount="%d" columncount="%d" sheetcount="%d">\n'
                   '%s   </v:imagestack>\n  </v:image3d>\n'
                   '  <v:functionfromimage3d id="%d" image3did="%d" filter="nearest" tilestyleu="clamp" '
                   'tilestylev="clamp" tilestylew="clamp"/>\n') % (2 + 2 * i, name, rows, COLS, SHEETS, sheets, 3 + 2 * i, 2 + 2 * i)
    # u = (x - 10) / 4, v = (y - 20) / 3, w = z / 2
    t_map = "0.25 0 0 0 0.33333333333333331 0 0 0 0.5 -2.5 -6.666666666666667 0"
    return ('<?xml version="1.0" encoding="UTF-8"?>\n'
            '<model unit="millimeter" xml:lang="en-US" xmlns="%s" xmlns:v="%s">\n'
            ' <resources>\n'
            '  <basematerials id="1">\n   <base name="Vero Cyan" displaycolor="#00A0E0"/>\n'
            '   <base name="Agilus" displaycolor="#202020"/>\n  </basematerials>\n'
            '%s'
            '  <v:volumedata id="6">\n   <v:composite basematerialid="1">\n'
            '    <v:materialmapping functionid="3" channel="red" transform="%s"/>\n'
            '    <v:materialmapping functionid="5" channel="red" transform="%s"/>\n'
            '   </v:composite>\n  </v:volumedata>\n'
            '  <object id="7" type="model">\n   <mesh v:volumeid="6">\n    <vertices>\n%s    </vertices>\n'
            '    <triangles>\n%s    </triangles>\n   </mesh>\n  </object>\n'
            ' </resources>\n <build>\n  <item objectid="7"/>\n </build>\n</model>\n') % (CORE, VOL, stacks, t_map, t_map, v, t)


CONTENT_TYPES = ('<?xml version="1.0" encoding="UTF-8"?>\n'
                 '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
                 '<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
                 '<Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>'
                 '<Default Extension="png" ContentType="image/png"/></Types>\n')
RELS = ('<?xml version="1.0" encoding="UTF-8"?>\n'
        '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
        '<Relationship Target="/3D/3dmodel.model" Id="rel0" '
        'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>\n')


def package(path, rows=ROWS, skip=()):
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        def add(name, data):
            if name in skip:
                return
            info = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info, data)
        add("[Content_Types].xml", CONTENT_TYPES)
        add("_rels/.rels", RELS)
        add("3D/3dmodel.model", model(rows))
        for name in ("cyan", "agilus"):
            for k in range(SHEETS):
                add("3D/volumetric/%s/sheet%04d.png" % (name, k + 1), sheet(name))


package("tests/data/good/volumetric_box.3mf")
with open("tests/data/good/volumetric_box.3mf", "rb") as f:
    data = f.read()
with open("tests/data/bad/3mf_truncated.3mf", "wb") as f:
    f.write(data[: len(data) // 2])
package("tests/data/bad/3mf_no_model.3mf", skip=("3D/3dmodel.model",))
package("tests/data/bad/3mf_missing_image.3mf", skip=("3D/volumetric/agilus/sheet0002.png",))
package("tests/data/bad/3mf_bad_dimensions.3mf", rows=4)
