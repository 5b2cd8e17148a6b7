#!/usr/bin/env python3
"""tests/data/make/mesh_formats.py - writes the 3MF, OBJ and PLY files of tests/data/good and
tests/data/bad (run from the repository root; the output is deterministic: fixed ZIP dates).
The 3MF packages are written by hand here, not by lib3mf, so that they can be wrong in exactly
one way each; the unit tests (tests/io/3mf/test_mesh_read.c) also read packages lib3mf writes."""
import io
import struct
import zipfile

CT = ('<?xml version="1.0" encoding="UTF-8"?>\n<Types xmlns="http://schemas.openxmlformats.org/package/2006/'
      'content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships'
      '+xml"/><Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>'
      '</Types>')
RELS = ('<?xml version="1.0" encoding="UTF-8"?>\n<Relationships xmlns="http://schemas.openxmlformats.org/package/'
        '2006/relationships"><Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/'
        '3dmanufacturing/2013/01/3dmodel"/></Relationships>')
HEAD = ('<?xml version="1.0" encoding="UTF-8"?>\n<model unit="%s" xml:lang="en-US" xmlns="http://schemas.microsoft'
        '.com/3dmanufacturing/core/2015/02" xmlns:m="http://schemas.microsoft.com/3dmanufacturing/material/2015/02">\n')
MATS = ('<basematerials id="5"><base name="VeroWhite" displaycolor="#F0F0F0"/>'
        '<base name="Agilus30" displaycolor="#202020"/></basematerials>\n')


def box(lo, hi):
    v = [(x, y, z) for z in (lo, hi) for y in (lo, hi) for x in (lo, hi)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (1, 3, 7, 5), (3, 2, 6, 7), (2, 0, 4, 6)]
    t = []
    for a, b, c, d in quads:
        t += [(a, b, c), (a, c, d)]
    return v, t


def mesh_xml(v, t, tri_attrs=None):
    s = '<mesh><vertices>' + ''.join('<vertex x="%s" y="%s" z="%s"/>' % p for p in v) + '</vertices><triangles>'
    for i, (a, b, c) in enumerate(t):
        extra = (tri_attrs or {}).get(i, '')
        s += '<triangle v1="%d" v2="%d" v3="%d"%s/>' % (a, b, c, extra)
    return s + '</triangles></mesh>'


def package(path, model, parts=('ct', 'rels', 'model')):
    """Write the package to path (a file name or a file object)."""
    with zipfile.ZipFile(path, 'w', zipfile.ZIP_DEFLATED) as z:
        for name, text, key in (('[Content_Types].xml', CT, 'ct'), ('_rels/.rels', RELS, 'rels'),
                                ('3D/3dmodel.model', model, 'model')):
            if key in parts:
                z.writestr(zipfile.ZipInfo(name, (2024, 1, 1, 0, 0, 0)), text, zipfile.ZIP_DEFLATED)


def tet(v3='0 0 1', tris=((0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)), attrs='', tri_attrs=None, oid=1, name='tet'):
    v = [('0', '0', '0'), ('1', '0', '0'), ('0', '1', '0'), tuple(v3.split())]
    return '<object id="%d" name="%s" type="model"%s>%s</object>' % (oid, name, attrs, mesh_xml(v, tris, tri_attrs))


def model(resources, items='<item objectid="1"/>', unit='millimeter'):
    return HEAD % unit + '<resources>' + resources + '</resources><build>' + items + '</build></model>\n'


# ---- good -------------------------------------------------------------------------------------
ov, ot = box(0, 10)
iv, it = box(3, 7)
package('tests/data/good/two_boxes.3mf', model(
    MATS + '<object id="2" name="outer" type="model" pid="5" pindex="0">' + mesh_xml(ov, ot) + '</object>'
    '<object id="3" name="inner" type="model" pid="5" pindex="1">' + mesh_xml(iv, it) + '</object>',
    '<item objectid="2"/><item objectid="3" transform="1 0 0 0 1 0 0 0 1 0 0 0"/>'))
# a CAD assembly that does not overlap: a Vero shell with a cavity (the outer box outward, the
# cavity's faces inward) and the Agilus core that fills the cavity, listed shell first
sv = ov + iv
st = ot + [(c + 8, b + 8, a + 8) for a, b, c in it]
package('tests/data/good/core_in_shell.3mf', model(
    MATS + '<object id="2" name="shell" type="model" pid="5" pindex="0">' + mesh_xml(sv, st) + '</object>'
    '<object id="3" name="core" type="model" pid="5" pindex="1">' + mesh_xml(iv, it) + '</object>',
    '<item objectid="2"/><item objectid="3"/>'))
with open('tests/data/good/groups.obj', 'w') as f:
    f.write('# two cubes: an outer shell and an inner core, as a CAD exporter writes them\nmtllib parts.mtl\n')
    for p in ov + iv:
        f.write('v %s %s %s\n' % p)
    for name, mat, base in (('shell', 'VeroWhite', 1), ('core', 'Agilus30', 9)):
        f.write('o %s\nusemtl %s\ns off\n' % (name, mat))
        for a, b, c in ot:
            f.write('f %d %d %d\n' % (a + base, b + base, c + base))
with open('tests/data/good/tet_binary_be.ply', 'wb') as f:
    f.write(b'ply\nformat binary_big_endian 1.0\ncomment a tetrahedron\nelement vertex 4\nproperty double x\n'
            b'property float y\nproperty short z\nelement face 4\nproperty list uchar uint vertex_indices\nend_header\n')
    for x, y, z in ((0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)):
        f.write(struct.pack('>dfh', x, y, z))
    for t in ((0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)):
        f.write(struct.pack('>BIII', 3, *t))

# ---- bad --------------------------------------------------------------------------------------
package('tests/data/bad/3mf_missing_model.3mf', model(tet()), parts=('ct', 'rels'))
package('tests/data/bad/3mf_index_out_of_range.3mf', model(tet(tris=((0, 2, 1), (0, 1, 3), (1, 2, 7), (0, 3, 2)))))
package('tests/data/bad/3mf_missing_material.3mf', model(MATS + tet(attrs=' pid="5" pindex="0"',
                                                                     tri_attrs={2: ' pid="9" p1="0"'})))
package('tests/data/bad/3mf_material_past_end.3mf', model(MATS + tet(attrs=' pid="5" pindex="0"',
                                                                      tri_attrs={3: ' p1="2"'})))
package('tests/data/bad/3mf_nan_vertex.3mf', model(tet(v3='0 NaN 1')))
package('tests/data/bad/3mf_unknown_component.3mf', model(
    tet() + '<object id="2" name="assembly" type="model"><components><component objectid="1"/>'
    '<component objectid="5"/></components></object>', '<item objectid="2"/>'))
# issue 27: what other producers write and hovox reads (with one warning), or refuses by name
package('tests/data/good/3mf_loose_pid.3mf', model(MATS + tet(tri_attrs={0: ' pid="5" p1="1"', 1: ' pid="5" p1="0"',
                                                                   2: ' pid="5" p1="0"', 3: ' pid="5" p1="0"'})))
package('tests/data/bad/3mf_singular_transform.3mf', model(tet(), '<item objectid="1" transform="1 0 0 0 1 0 0 0 0 0 0 0"/>'))
package('tests/data/bad/3mf_cyclic_component.3mf', model(
    tet() + '<object id="2" name="loop" type="model"><components><component objectid="2"/></components></object>',
    '<item objectid="2"/>'))
package('tests/data/bad/3mf_unknown_unit.3mf', model(tet(), unit='furlong'))
# a component's transform that is not finite (a producer's overflow): refused naming the object
package('tests/data/bad/3mf_nonfinite_transform.3mf', model(
    tet() + '<object id="2" name="pair" type="model"><components><component objectid="1"/>'
    '<component objectid="1" transform="1 0 0 0 1 0 0 0 1 1e999 0 0"/></components></object>', '<item objectid="2"/>'))
package('tests/data/bad/3mf_beam_lattice.3mf', model(
    '<object id="1" name="lattice" type="model"><mesh><vertices><vertex x="0" y="0" z="0"/><vertex x="0" y="0" z="10"/>'
    '</vertices><triangles/><b:beamlattice xmlns:b="http://schemas.microsoft.com/3dmanufacturing/beamlattice/2017/02" '
    'minlength="0.1" radius="1"><b:beams><b:beam v1="0" v2="1"/></b:beams></b:beamlattice></mesh></object>'))
# issue 27 item 4: info reports the unit, the build items and their transforms (a support item
# is no body; an item of components is one)
package('tests/data/good/3mf_items_inch.3mf', model(
    tet() + tet(oid=2, name='brace') + '<object id="3" name="pair" type="model"><components><component objectid="1"/>'
    '<component objectid="1" transform="1 0 0 0 1 0 0 0 1 2 0 0"/></components></object>',
    '<item objectid="3" transform="0 1 0 -1 0 0 0 0 1 5 0 0"/><item objectid="2" transform="1 0 0 0 1 0 0 0 1 0 0 3"/>',
    unit='inch').replace('name="brace" type="model"', 'name="brace" type="support"'))
# issue 27: composite materials are material fractions; a multiproperties' material layer gives
# the material, its colour layer the colour. The Vero shell and its core of 25 % Vero, 75 % Agilus
# (composite 6#0), and a tab beside them of a multi (8#0: composite 6#1, half and half, in the
# colour #3060C0 of colour group 7)
tv, tt = box(12, 14)
COMPOSITES = ('<m:compositematerials id="6" matid="5" matindices="0 1"><m:composite values="0.25 0.75"/>'
              '<m:composite values="0.5 0.5"/></m:compositematerials>\n'
              '<m:colorgroup id="7"><m:color color="#3060C0"/></m:colorgroup>\n'
              '<m:multiproperties id="8" pids="6 7"><m:multi pindices="1 0"/></m:multiproperties>\n')
package('tests/data/good/composite_core.3mf', model(
    MATS + COMPOSITES + '<object id="2" name="shell" type="model" pid="5" pindex="0">' + mesh_xml(sv, st) + '</object>'
    '<object id="3" name="core" type="model" pid="6" pindex="0">' + mesh_xml(iv, it) + '</object>'
    '<object id="4" name="tab" type="model" pid="8" pindex="0">' + mesh_xml(tv, tt) + '</object>',
    '<item objectid="2"/><item objectid="3"/><item objectid="4"/>'))
package('tests/data/bad/3mf_composite_sum.3mf', model(
    MATS + COMPOSITES.replace('"0.5 0.5"', '"0.5 0.4"') + tet(attrs=' pid="6" pindex="0"')))


# issue 27 item 4: texture, composite and nested components in one package, written the way a
# slicer writes its projects: metadata, its own namespace's attributes, Production extension
# UUIDs (declared, not required), no default pid on the textured object (its triangles name their
# properties), a thumbnail, the texture related from the model part. A VeroWhite plate 20 x 20 x
# 2 mm, its top textured; a core of composite 0.3 VeroWhite + 0.7 Agilus30 placed by a component
# transform; two Agilus30 pegs, a component object of their own, turned 90 degrees about z by the
# assembly that holds it; the assembly one build item, moved by (5, 5, 0).
def cuboid(lo, hi):
    v = [(x, y, z) for z in (lo[2], hi[2]) for y in (lo[1], hi[1]) for x in (lo[0], hi[0])]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (1, 3, 7, 5), (3, 2, 6, 7), (2, 0, 4, 6)]
    t = []
    for q in quads:
        t += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    return [tuple('%g' % c for c in p) for p in v], t


def png_rgb(w, h, pixel):
    import zlib
    raw = b''.join(b'\0' + bytes(c for x in range(w) for c in pixel(x, y)) for y in range(h))
    def chunk(kind, data):
        return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data) & 0xFFFFFFFF)
    return (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0)) +
            chunk(b'IDAT', zlib.compress(raw, 9)) + chunk(b'IEND', b''))


SLICER_HEAD = ('<?xml version="1.0" encoding="UTF-8"?>\n<model unit="millimeter" xml:lang="en-US" '
               'xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02" '
               'xmlns:m="http://schemas.microsoft.com/3dmanufacturing/material/2015/02" '
               'xmlns:p="http://schemas.microsoft.com/3dmanufacturing/production/2015/06" '
               'xmlns:slic3rpe="http://schemas.slic3r.org/3mf/2017/06">\n'
               '<metadata name="Application">a slicer 2.7</metadata>\n<metadata name="Title">textured assembly'
               '</metadata>\n<metadata name="slic3rpe:Version3mf">1</metadata>\n')
pv, pt = cuboid((0, 0, 0), (20, 20, 2))
top = {2, 3}  # the plate's top face: textured, corners at the texture's corners
plate_attrs = {}
for i in range(len(pt)):
    plate_attrs[i] = ' pid="4" p1="0" p2="1" p3="2"' if i == 2 else (' pid="4" p1="0" p2="2" p3="3"' if i == 3
                                                                     else ' pid="1" p1="0"')
cv, ct = cuboid((0, 0, 0), (8, 8, 4))
gv, gt = cuboid((0, 0, 0), (2, 2, 3))
slicer = (SLICER_HEAD + '<resources>\n'
          '<m:basematerials id="1"><m:base name="VeroWhite" displaycolor="#F0F0F0"/>'
          '<m:base name="Agilus30" displaycolor="#202020"/></m:basematerials>\n'
          '<m:compositematerials id="2" matid="1" matindices="0 1"><m:composite values="0.3 0.7"/>'
          '</m:compositematerials>\n'
          '<m:texture2d id="3" path="/3D/Textures/checker.png" contenttype="image/png" tilestyleu="wrap" '
          'tilestylev="wrap" filter="nearest"/>\n'
          '<m:texture2dgroup id="4" texid="3"><m:tex2coord u="0" v="0"/><m:tex2coord u="0" v="1"/>'
          '<m:tex2coord u="1" v="1"/><m:tex2coord u="1" v="0"/></m:texture2dgroup>\n'
          '<object id="10" name="plate" type="model" p:UUID="00000010-81cb-4c03-9d28-80fed5dfa1dc">' +
          mesh_xml(pv, pt, plate_attrs) + '</object>\n'
          '<object id="11" name="core" type="model" pid="2" pindex="0" p:UUID="00000011-81cb-4c03-9d28-80fed5dfa1dc">' +
          mesh_xml(cv, ct) + '</object>\n'
          '<object id="12" name="peg" type="model" pid="1" pindex="1" p:UUID="00000012-81cb-4c03-9d28-80fed5dfa1dc">' +
          mesh_xml(gv, gt) + '</object>\n'
          '<object id="20" name="pegs" type="model" p:UUID="00000020-81cb-4c03-9d28-80fed5dfa1dc"><components>'
          '<component objectid="12" p:UUID="00000021-81cb-4c03-9d28-80fed5dfa1dc"/>'
          '<component objectid="12" transform="1 0 0 0 1 0 0 0 1 16 0 0"/></components></object>\n'
          '<object id="21" name="assembly" type="model" p:UUID="00000022-81cb-4c03-9d28-80fed5dfa1dc"><components>'
          '<component objectid="10"/>'
          '<component objectid="11" transform="1 0 0 0 1 0 0 0 1 6 6 2"/>'
          '<component objectid="20" transform="0 1 0 -1 0 0 0 0 1 3 1 2"/></components></object>\n'
          '</resources>\n<build p:UUID="00000030-81cb-4c03-9d28-80fed5dfa1dc">'
          '<item objectid="21" transform="1 0 0 0 1 0 0 0 1 5 5 0" printable="1" '
          'p:UUID="00000031-81cb-4c03-9d28-80fed5dfa1dc"/></build>\n</model>\n')
SLICER_CT = CT.replace('</Types>', '<Default Extension="png" ContentType="image/png"/></Types>')
SLICER_RELS = RELS.replace('</Relationships>', '<Relationship Target="/Metadata/thumbnail.png" Id="rel1" '
                           'Type="http://schemas.openxmlformats.org/package/2006/relationships/metadata/thumbnail"/>'
                           '</Relationships>')
MODEL_RELS = ('<?xml version="1.0" encoding="UTF-8"?>\n<Relationships xmlns="http://schemas.openxmlformats.org/'
              'package/2006/relationships"><Relationship Target="/3D/Textures/checker.png" Id="rel2" '
              'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dtexture"/></Relationships>')
checker = png_rgb(8, 8, lambda x, y: (200, 40, 40) if (x + y) % 2 else (40, 40, 200))
thumb = png_rgb(4, 4, lambda x, y: (128, 128, 128))
with zipfile.ZipFile('tests/data/good/slicer_assembly.3mf', 'w', zipfile.ZIP_DEFLATED) as z:
    for name, data in (('[Content_Types].xml', SLICER_CT), ('_rels/.rels', SLICER_RELS), ('3D/3dmodel.model', slicer),
                       ('3D/_rels/3dmodel.model.rels', MODEL_RELS), ('3D/Textures/checker.png', checker),
                       ('Metadata/thumbnail.png', thumb)):
        z.writestr(zipfile.ZipInfo(name, (2024, 1, 1, 0, 0, 0)), data, zipfile.ZIP_DEFLATED)
# Production extension (as Bambu Studio and OrcaSlicer write projects): the root model requires
# p and holds one object of components whose meshes are in another model part (p:path), with its
# own ids (1 and 2, the root's assembly being 2 too) and its own base materials: core_in_shell's
# VeroWhite shell and Agilus30 core, the assembly moved by (10, 0, 0)
PROD = 'http://schemas.microsoft.com/3dmanufacturing/production/2015/06'
U = '-81cb-4c03-9d28-80fed5dfa1dc"'
parts_model = (HEAD % 'millimeter').replace('material/2015/02">', 'material/2015/02" xmlns:p="%s" requiredextensions="p">' % PROD, 1) + (
    '<resources>' + MATS + '<object id="1" name="shell" type="model" pid="5" pindex="0" p:UUID="00000001' + U + '>' +
    mesh_xml(sv, st) + '</object><object id="2" name="core" type="model" pid="5" pindex="1" p:UUID="00000002' + U +
    '>' + mesh_xml(iv, it) + '</object></resources><build/></model>\n')
root_model = (HEAD % 'millimeter').replace('material/2015/02">', 'material/2015/02" xmlns:p="%s" requiredextensions="p">' % PROD, 1) + (
    '<metadata name="Application">BambuStudio-01.09</metadata><resources>'
    '<object id="2" name="core_in_shell" type="model" p:UUID="00000003' + U + '><components>'
    '<component p:path="/3D/Objects/object_1.model" objectid="1" p:UUID="00000004' + U + ' transform="1 0 0 0 1 0 0 0 1 10 0 0"/>'
    '<component p:path="/3D/Objects/object_1.model" objectid="2" p:UUID="00000005' + U + ' transform="1 0 0 0 1 0 0 0 1 10 0 0"/>'
    '</components></object></resources><build p:UUID="00000006' + U + '><item objectid="2" p:UUID="00000007' + U +
    ' printable="1"/></build></model>\n')
PARTS_RELS = ('<?xml version="1.0" encoding="UTF-8"?>\n<Relationships xmlns="http://schemas.openxmlformats.org/package/'
              '2006/relationships"><Relationship Target="/3D/Objects/object_1.model" Id="rel1" Type="http://schemas.'
              'microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>')
with zipfile.ZipFile('tests/data/good/production_parts.3mf', 'w', zipfile.ZIP_DEFLATED) as z:
    for name, data in (('[Content_Types].xml', CT), ('_rels/.rels', RELS), ('3D/3dmodel.model', root_model),
                       ('3D/_rels/3dmodel.model.rels', PARTS_RELS), ('3D/Objects/object_1.model', parts_model)):
        z.writestr(zipfile.ZipInfo(name, (2024, 1, 1, 0, 0, 0)), data, zipfile.ZIP_DEFLATED)
buf = io.BytesIO()
package(buf, model(tet()))
good = buf.getvalue()
with open('tests/data/bad/3mf_truncated_zip.3mf', 'wb') as f:
    f.write(good[:len(good) * 2 // 3])
with open('tests/data/bad/3mf_not_zip.3mf', 'w') as f:
    f.write('solid not a 3mf\n')

TET_OBJ = 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n'
bad_obj = {
    'obj_bad_index': TET_OBJ + 'f 1 3 2\nf 1 2 4\nf 2 3 5\nf 1 4 3\n',
    'obj_forward_reference': 'v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n',
    'obj_zero_index': TET_OBJ + 'f 0 1 2\n',
    'obj_nan_vertex': 'v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n',
    'obj_bad_number': 'v 0 0 0\nv 1 0 0\nv 0 1 0.5.5\nf 1 2 3\n',
    'obj_short_face': TET_OBJ + 'f 1 2\n',
    'obj_no_faces': TET_OBJ + 'l 1 2 3 4\n',
}
for name, text in bad_obj.items():
    with open('tests/data/bad/%s.obj' % name, 'w') as f:
        f.write(text)

PLY_HEAD = ('ply\nformat %s 1.0\nelement vertex %s\nproperty float x\nproperty float y\nproperty float z\n'
            'element face %s\nproperty list uchar int vertex_indices\nend_header\n')
TET_V = ((0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1))
TET_F = ((0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2))


def ply_binary(path, nv, nf, verts, faces, cut=0):
    data = (PLY_HEAD % ('binary_little_endian', nv, nf)).encode()
    for p in verts:
        data += struct.pack('<fff', *p)
    for t in faces:
        data += struct.pack('<Biii', 3, *t)
    with open(path, 'wb') as f:
        f.write(data[:len(data) - cut])


ply_binary('tests/data/bad/ply_count_lies.ply', 1000000000000, 4, TET_V, TET_F)
ply_binary('tests/data/bad/ply_bad_index.ply', 4, 4, TET_V, ((0, 2, 1), (0, 1, 3), (1, 2, 4), (0, 3, 2)))
ply_binary('tests/data/bad/ply_truncated.ply', 4, 4, TET_V, TET_F, cut=6)
ply_binary('tests/data/bad/ply_nan_vertex.ply', 4, 4, ((0, 0, 0), (1, 0, 0), (0, float('nan'), 0), (0, 0, 1)), TET_F)
with open('tests/data/bad/ply_ascii_bad_value.ply', 'w') as f:
    f.write(PLY_HEAD % ('ascii', 4, 4) + '0 0 0\n1 0 0\n0 1 0\n0 0 one\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n')
with open('tests/data/bad/ply_no_faces.ply', 'w') as f:
    f.write('ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n'
            'end_header\n0 0 0\n')


# ---- other producers' conventions (a new user's files, suser) ---------------------------------
def streamed(path, parts):
    """A package written to a pipe, as a streaming producer writes it: each part's sizes in a data
    descriptor after its data, ZIP64 extra fields (3MF Core 1.1: consumers MUST read both)."""
    class Pipe(io.RawIOBase):
        def __init__(self, f):
            self.f = f

        def writable(self):
            return True

        def write(self, b):
            return self.f.write(b)
    with open(path, 'wb') as raw, zipfile.ZipFile(Pipe(raw), 'w', zipfile.ZIP_DEFLATED) as z:
        for name, data in parts:
            with z.open(zipfile.ZipInfo(name, (2024, 1, 1, 0, 0, 0)), 'w', force_zip64=True) as f:
                f.write(data)


# A hand writer's package: a UTF-8 byte order mark, CRLF lines, the core namespace on a prefix,
# attributes in another order and in single quotes, coordinates padded with white space (an
# ST_Number collapses it, Core 2.3.4), a transform spread over lines; the box 10 x 6 x 4 turned a
# quarter about z and moved by (20, 5, 1): x 14..20, y 5..15, z 1..5, volume 240
hv, ht = cuboid((0, 0, 0), (10, 6, 4))
hand = ('<?xml version="1.0" encoding="UTF-8"?>\r\n<c:model xmlns:c="http://schemas.microsoft.com/3dmanufacturing/'
        "core/2015/02\" xml:lang='en-GB' unit='millimeter'>\r\n<c:metadata name='Title'>hand written</c:metadata>\r\n"
        '<c:resources>\r\n<c:object name=\'box\' type="model" id=\'7\'>\r\n<c:mesh>\r\n<c:vertices>\r\n' +
        ''.join("<c:vertex z=' %s ' y='%6s  ' x=\"\t%s\"/>\r\n" % (z, y, x) for x, y, z in hv) +
        '</c:vertices>\r\n<c:triangles>\r\n' +
        ''.join("<c:triangle v3='%d' v1='%d' v2='%d'/>\r\n" % (c, a, b) for a, b, c in ht) +
        "</c:triangles>\r\n</c:mesh>\r\n</c:object>\r\n</c:resources>\r\n<c:build>\r\n"
        "<c:item transform='0 1 0\r\n -1 0 0\r\n 0 0 1\r\n 20 5 1 ' objectid='7'/>\r\n</c:build>\r\n</c:model>\r\n")
streamed('tests/data/good/3mf_hand_writer.3mf', [('[Content_Types].xml', CT.encode()), ('_rels/.rels', RELS.encode()),
                                                 ('3D/3dmodel.model', b'\xef\xbb\xbf' + hand.encode())])
# A part and the support it stands on, one object of components (Core 4.1: "support" objects
# SHOULD be referenced in an object with the "model" they support, and a manufacturing device
# MUST NOT fill them): the part is the 10 mm cube (volume 1000), the support a tetrahedron beside
# it at x 12..15, which is no part of the print
sv2, st2 = cuboid((0, 0, 0), (10, 10, 10))
package('tests/data/good/3mf_support_component.3mf', model(
    '<object id="1" name="part" type="model">' + mesh_xml(sv2, st2) + '</object>' +
    tet(oid=2, name='prop').replace('type="model"', 'type="support"') +
    '<object id="3" name="part and prop" type="model"><components><component objectid="1"/>'
    '<component objectid="2" transform="3 0 0 0 3 0 0 0 3 12 0 0"/></components></object>',
    '<item objectid="3"/>'))
# PrusaSlicer 2.5's project layout: an object's volumes all in its one <mesh>, listed in
# Metadata/Slic3r_PE_model.config as ranges of its triangles with their types; the build item
# its instance, with PrusaSlicer's own (unprefixed) printable attribute. A 20 x 20 x 10 part, a
# settings modifier overlapping it and a negative volume inside it. PrusaSlicer 2.5 itself
# (prusa-slicer --export-stl) exports the part alone: 12 facets, volume 4000, x 100..120, z 0..10
PS_NS = 'xmlns:slic3rpe="http://schemas.slic3r.org/3mf/2017/06"'
ps_vols = [('part', 'ModelPart', cuboid((0, 0, 0), (20, 20, 10))), ('infill', 'ParameterModifier', cuboid((5, 5, 5), (30, 15, 20))),
           ('hole', 'NegativeVolume', cuboid((5, 5, 5), (15, 15, 20)))]
ps_v, ps_t, ps_cfg = [], [], ''
for vname, vtype, (cv_, ct_) in ps_vols:
    off, first = len(ps_v), len(ps_t)
    ps_v += cv_
    ps_t += [(a + off, b + off, c + off) for a, b, c in ct_]
    ps_cfg += ('  <volume firstid="%d" lastid="%d">\n   <metadata type="volume" key="name" value="%s"/>\n'
               '   <metadata type="volume" key="volume_type" value="%s"/>\n'
               '   <metadata type="volume" key="matrix" value="1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1"/>\n'
               '   <mesh edges_fixed="0" degenerate_facets="0" facets_removed="0" facets_reversed="0" backwards_edges="0"/>\n'
               '  </volume>\n' % (first, len(ps_t) - 1, vname, vtype))
ps_model = ('<?xml version="1.0" encoding="UTF-8"?>\n<model unit="millimeter" xml:lang="en-US" xmlns="http://schemas.'
            'microsoft.com/3dmanufacturing/core/2015/02" %s>\n <metadata name="slic3rpe:Version3mf">1</metadata>\n'
            ' <metadata name="Application">PrusaSlicer-2.5.0</metadata>\n <resources>\n  <object id="1" type="model">\n'
            '   %s\n  </object>\n </resources>\n <build>\n  <item objectid="1" transform="1 0 0 0 1 0 0 0 1 100 100 0" '
            'printable="1"/>\n </build>\n</model>\n' % (PS_NS, mesh_xml(ps_v, ps_t)))
ps_config = ('<?xml version="1.0" encoding="UTF-8"?>\n<config>\n <object id="1" instances_count="1">\n'
             '  <metadata type="object" key="name" value="bracket.stl"/>\n' + ps_cfg + ' </object>\n</config>\n')
with zipfile.ZipFile('tests/data/good/3mf_prusaslicer_volumes.3mf', 'w', zipfile.ZIP_DEFLATED) as z:
    for name, data in (('[Content_Types].xml', CT), ('_rels/.rels', RELS), ('3D/3dmodel.model', ps_model),
                       ('Metadata/Slic3r_PE_model.config', ps_config)):
        z.writestr(zipfile.ZipInfo(name, (2024, 1, 1, 0, 0, 0)), data, zipfile.ZIP_DEFLATED)
# Bambu Studio's (and OrcaSlicer's) project layout: the root model requires p and holds one object
# of components, each placing a mesh object of /3D/Objects/object_1.model; Metadata/model_settings.config
# types each part (<part id> the component's objectid): the 20 x 20 x 10 body a normal_part, a box
# overlapping it a modifier_part, a box beside it a support_blocker. The item moves it by (50, 60, 0):
# the body alone, 12 facets, volume 4000, x 50..70, y 60..80, z 0..10
bb_parts = [(1, 'body', 'normal_part', cuboid((0, 0, 0), (20, 20, 10))), (3, 'dense', 'modifier_part', cuboid((5, 5, 5), (30, 15, 20))),
            (4, 'no support', 'support_blocker', cuboid((25, 0, 0), (30, 5, 5)))]
bb_objects = ('<?xml version="1.0" encoding="UTF-8"?>\n<model unit="millimeter" xml:lang="en-US" xmlns="http://schemas.microsoft.'
              'com/3dmanufacturing/core/2015/02" xmlns:BambuStudio="http://schemas.bambulab.com/package/2021" xmlns:p="%s" '
              'requiredextensions="p">\n <metadata name="BambuStudio:3mfVersion">1</metadata>\n <resources>\n' % PROD +
              ''.join('  <object id="%d" p:UUID="0000000%d%s type="model">\n   %s\n  </object>\n' % (i, i, U, mesh_xml(v_, t_))
                      for i, _, _, (v_, t_) in bb_parts) + ' </resources>\n <build/>\n</model>\n')
bb_root = ('<?xml version="1.0" encoding="UTF-8"?>\n<model unit="millimeter" xml:lang="en-US" xmlns="http://schemas.microsoft.'
           'com/3dmanufacturing/core/2015/02" xmlns:BambuStudio="http://schemas.bambulab.com/package/2021" xmlns:p="%s" '
           'requiredextensions="p">\n <metadata name="Application">BambuStudio-01.09.07.52</metadata>\n'
           ' <metadata name="BambuStudio:3mfVersion">1</metadata>\n <resources>\n'
           '  <object id="2" p:UUID="00000002%s type="model">\n   <components>\n' % (PROD, U) +
           ''.join('    <component p:path="/3D/Objects/object_1.model" objectid="%d" p:UUID="0001000%d%s transform="1 0 0 0 1 0 0 0 1 0 0 0"/>\n'
                   % (i, i, U) for i, _, _, _ in bb_parts) +
           '   </components>\n  </object>\n </resources>\n <build p:UUID="00000009%s>\n' % U +
           '  <item objectid="2" p:UUID="0000000a%s transform="1 0 0 0 1 0 0 0 1 50 60 0" printable="1"/>\n </build>\n</model>\n' % U)
bb_config = ('<?xml version="1.0" encoding="UTF-8"?>\n<config>\n  <object id="2">\n    <metadata key="name" value="bracket"/>\n'
             '    <metadata key="extruder" value="1"/>\n' +
             ''.join('    <part id="%d" subtype="%s">\n      <metadata key="name" value="%s"/>\n'
                     '      <metadata key="matrix" value="1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1"/>\n    </part>\n' % (i, sub, n_)
                     for i, n_, sub, _ in bb_parts) +
             '  </object>\n  <plate>\n    <metadata key="plater_id" value="1"/>\n    <model_instance>\n'
             '      <metadata key="object_id" value="2"/>\n      <metadata key="instance_id" value="0"/>\n'
             '    </model_instance>\n  </plate>\n</config>\n')
BB_RELS = PARTS_RELS
with zipfile.ZipFile('tests/data/good/3mf_bambu_parts.3mf', 'w', zipfile.ZIP_DEFLATED) as z:
    for name, data in (('[Content_Types].xml', CT), ('_rels/.rels', RELS), ('3D/3dmodel.model', bb_root),
                       ('3D/_rels/3dmodel.model.rels', BB_RELS), ('3D/Objects/object_1.model', bb_objects),
                       ('Metadata/model_settings.config', bb_config)):
        z.writestr(zipfile.ZipInfo(name, (2024, 1, 1, 0, 0, 0)), data, zipfile.ZIP_DEFLATED)
