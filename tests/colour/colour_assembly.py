#!/usr/bin/python3
"""tests/colour/colour_assembly.py DIR - coloured 3MF assemblies written by Python's zipfile (not by
hovox), for issue 29 item 2 (assemblies painted by body):
  DIR/badge.3mf   three build items side by side or stacked: "base", a 20 x 20 x 4 mm plate of the
                  base material Agilus30Black (a resin of the printer's table, displaycolor #383838);
                  "badge", a 12 x 12 x 4 mm block on it (x, y 4..16, z 4..8) in a colour group's
                  #C01010; "grip", an 8 x 20 x 4 mm block beside the plate (x 22..30) of the base
                  material "PLA Blue" (no resin, displaycolor #2050C0)
  DIR/resins.3mf  two blocks of base materials that are both resins (VeroCyan-V, Agilus30Black)"""
import os
import sys
import zipfile

CORE = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"
MAT = "http://schemas.microsoft.com/3dmanufacturing/material/2015/02"
QUADS = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]


def box(oid, name, lo, hi, pid, pindex):
    verts = [(hi[0] if c & 1 else lo[0], hi[1] if c & 2 else lo[1], hi[2] if c & 4 else lo[2]) for c in range(8)]
    tris = [t for q in QUADS for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    v = "".join('     <vertex x="%g" y="%g" z="%g"/>\n' % p for p in verts)
    t = "".join('     <triangle v1="%d" v2="%d" v3="%d"/>\n' % p for p in tris)
    return ('  <object id="%d" name="%s" type="model" pid="%d" pindex="%d">\n   <mesh>\n    <vertices>\n%s'
            '    </vertices>\n    <triangles>\n%s    </triangles>\n   </mesh>\n  </object>\n') % (oid, name, pid, pindex, v, t)


def model(resources, items):
    build = "".join('  <item objectid="%d"/>\n' % i for i in items)
    return ('<?xml version="1.0" encoding="UTF-8"?>\n<model unit="millimeter" xml:lang="en-US" xmlns="%s" xmlns:m="%s">\n'
            ' <resources>\n%s </resources>\n <build>\n%s </build>\n</model>\n') % (CORE, MAT, resources, build)


TYPES = ('<?xml version="1.0" encoding="UTF-8"?>\n<Types xmlns="http://schemas.openxmlformats.org/package/2006/'
         'content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.'
         'relationships+xml"/><Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-'
         '3dmodel+xml"/></Types>\n')
RELS = ('<?xml version="1.0" encoding="UTF-8"?>\n<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/'
        'relationships"><Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/'
        '3dmanufacturing/2013/01/3dmodel"/></Relationships>\n')


def package(path, text):
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in (("[Content_Types].xml", TYPES), ("_rels/.rels", RELS), ("3D/3dmodel.model", text)):
            z.writestr(zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0)), data)


def main(out):
    os.makedirs(out, exist_ok=True)
    res = ('  <basematerials id="1">\n   <base name="Agilus30Black" displaycolor="#383838"/>\n'
           '   <base name="PLA Blue" displaycolor="#2050C0"/>\n  </basematerials>\n'
           '  <m:colorgroup id="2">\n   <m:color color="#C01010"/>\n  </m:colorgroup>\n')
    res += box(3, "base", (0, 0, 0), (20, 20, 4), 1, 0)
    res += box(4, "badge", (4, 4, 4), (16, 16, 8), 2, 0)
    res += box(5, "grip", (22, 0, 0), (30, 20, 4), 1, 1)
    package(os.path.join(out, "badge.3mf"), model(res, (3, 4, 5)))
    res = ('  <basematerials id="1">\n   <base name="VeroCyan-V" displaycolor="#009FE3"/>\n'
           '   <base name="Agilus30Black" displaycolor="#383838"/>\n  </basematerials>\n')
    res += box(3, "a", (0, 0, 0), (10, 10, 4), 1, 0) + box(4, "b", (12, 0, 0), (22, 10, 4), 1, 1)
    package(os.path.join(out, "resins.3mf"), model(res, (3, 4)))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else ".")
