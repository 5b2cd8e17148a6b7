#!/usr/bin/python3
"""tests/colour/check_assembly.py STACK LAYER NAME=X0,Y0,X1,Y1 ... - the resin shares of a halftone
stack's layer inside boxes on the layer (mm, the manifest's pixel grid), read with Pillow (not
hovox's code): per box its object pixels and each resin's share (those of 0.5 % and more), one line
a box. For issue 29 item 2: an assembly's bodies in resins stay in them, painted ones in colour."""
import json
import os
import sys

from PIL import Image


def main(stack, layer, boxes):
    m = json.load(open(os.path.join(stack, "manifest.json")))
    names = {e["palette_index"]: e["name"] for e in m["materials"]}
    (sx, sy), (x0, y0) = m["pixel_mm"], m["origin_mm"]
    im = Image.open(os.path.join(stack, "layer-%05d.png" % layer))
    w, h = im.size
    px = im.load()
    for spec in boxes:
        name, rect = spec.split("=")
        a, b, c, d = (float(v) for v in rect.split(","))
        count = {}
        for r in range(h):
            y = y0 + (r + 0.5) * sy
            if not b <= y <= d:
                continue
            for col in range(w):
                x = x0 + (col + 0.5) * sx
                if a <= x <= c and px[col, r]:
                    count[px[col, r]] = count.get(px[col, r], 0) + 1
        n = sum(count.values())
        shares = sorted(((v / n, names[k]) for k, v in count.items() if v / n >= 0.005), reverse=True) if n else []
        print("%-6s %6d pixels: %s" % (name, n, ", ".join("%s %.3f" % (k, s) for s, k in shares)))


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]), sys.argv[3:])
