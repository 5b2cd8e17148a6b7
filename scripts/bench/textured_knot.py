#!/usr/bin/python3
"""scripts/bench/textured_knot.py - the bench's torus knot in colour (issue 29): a binary STL
written again as OBJ + MTL + PNG, UVs by a cylindrical projection (u around z, v up z), the
texture a 256 x 256 sweep of hues and lightness (65,536 distinct texels), so painting the knot
converts many colours. Usage: textured_knot.py KNOT.stl OUT.obj"""
import colorsys
import math
import os
import struct
import sys

from PIL import Image


def main():
    stl, obj = sys.argv[1], sys.argv[2]
    base = os.path.splitext(obj)[0]
    data = open(stl, "rb").read()
    (n,) = struct.unpack_from("<I", data, 80)
    tris = [struct.unpack_from("<9f", data, 84 + 50 * i + 12) for i in range(n)]
    zs = [t[k] for t in tris for k in (2, 5, 8)]
    z0, z1 = min(zs), max(zs)
    verts, vidx, uvs, faces = [], {}, [], []
    for t in tris:
        face = []
        for k in range(3):
            p = t[3 * k:3 * k + 3]
            if p not in vidx:
                vidx[p] = len(verts) + 1
                verts.append(p)
            u = math.atan2(p[1], p[0]) / (2 * math.pi) + 0.5
            v = (p[2] - z0) / (z1 - z0)
            uvs.append((u, v))
            face.append((vidx[p], len(uvs)))
        faces.append(face)
    img = Image.new("RGB", (256, 256))
    px = img.load()
    for y in range(256):
        for x in range(256):
            r, g, b = colorsys.hls_to_rgb(x / 256, 0.25 + 0.5 * y / 255, 0.9)
            px[x, y] = (int(r * 255), int(g * 255), int(b * 255))
    img.save(base + ".png")
    name = os.path.basename(base)
    with open(base + ".mtl", "w") as f:
        f.write("newmtl knot\nKd 1 1 1\nmap_Kd %s.png\n" % name)
    with open(obj, "w") as f:
        f.write("mtllib %s.mtl\no knot\nusemtl knot\n" % name)
        f.writelines("v %.6g %.6g %.6g\n" % p for p in verts)
        f.writelines("vt %.6f %.6f\n" % uv for uv in uvs)
        f.writelines("f %d/%d %d/%d %d/%d\n" % (a[0], a[1], b[0], b[1], c[0], c[1]) for a, b, c in faces)


main()
