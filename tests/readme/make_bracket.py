#!/usr/bin/python3
"""tests/readme/make_bracket.py OUT.3mf - the README's bracket: a 3MF assembly of two objects, a base
plate 'base' in VeroWhite and a 'pad' on it in Agilus30, written the way a CAD exporter writes one
(Python's zipfile, not hovox)."""
import sys, zipfile

def box(x0, y0, z0, x1, y1, z1):
    v = [(x, y, z) for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)]
    t = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4),
         (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
    return v, t

def obj(oid, name, pindex, v, t):
    vs = ''.join('<vertex x="%g" y="%g" z="%g"/>' % p for p in v)
    ts = ''.join('<triangle v1="%d" v2="%d" v3="%d"/>' % f for f in t)
    return ('<object id="%d" type="model" name="%s" pid="1" pindex="%d"><mesh><vertices>%s</vertices>'
            '<triangles>%s</triangles></mesh></object>' % (oid, name, pindex, vs, ts))

model = ('<?xml version="1.0" encoding="UTF-8"?>\n'
         '<model unit="millimeter" xml:lang="en-US" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">'
         '<resources><basematerials id="1"><base name="VeroWhite" displaycolor="#F0F0F0"/>'
         '<base name="Agilus30" displaycolor="#202020"/></basematerials>'
         + obj(2, 'base', 0, *box(0, 0, 0, 40, 20, 4)) + obj(3, 'pad', 1, *box(10, 5, 4, 30, 15, 8)) +
         '</resources><build><item objectid="2"/><item objectid="3"/></build></model>\n')
with zipfile.ZipFile(sys.argv[1], 'w', zipfile.ZIP_DEFLATED) as z:
    z.writestr('[Content_Types].xml', '<?xml version="1.0" encoding="UTF-8"?>\n<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>\n')
    z.writestr('_rels/.rels', '<?xml version="1.0" encoding="UTF-8"?>\n<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>\n')
    z.writestr('3D/3dmodel.model', model)
