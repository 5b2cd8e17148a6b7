#!/usr/bin/python3
"""scripts/bench/split_obj.py - a binary STL as two OBJ files: one body, and the same facets in N
groups of consecutive facets (`g partK`), as CAD exporters write a part's faces (issue 32 item 20).
usage: split_obj.py MESH.stl N ONE.obj GROUPS.obj"""
import struct
import sys

src, groups, one, split = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
data = open(src, 'rb').read()
count = struct.unpack_from('<I', data, 80)[0]
index, verts, faces = {}, [], []
for i in range(count):
    base = 84 + 50 * i + 12
    face = []
    for k in range(3):
        p = struct.unpack_from('<3f', data, base + 12 * k)
        if p not in index:
            index[p] = len(verts) + 1
            verts.append(p)
        face.append(index[p])
    faces.append(face)
per = (len(faces) + groups - 1) // groups
for path, n in ((one, 1), (split, groups)):
    with open(path, 'w') as out:
        out.write(''.join('v %r %r %r\n' % v for v in verts))
        for i, f in enumerate(faces):
            if n > 1 and i % per == 0:
                out.write('g part%d\n' % (i // per))
            out.write('f %d %d %d\n' % tuple(f))
