#!/usr/bin/python3
"""tests/colour/check_tray_colour.py - a coloured mesh in a tray is painted as `layers` paints it
(issue 29, tray colour): the six-colour cube of check_paint.py (OBJ + MTL Kd), 6 mm, printed in one
step by `hovox layers cube.obj --place X,Y` and as `hovox tray --part cube.obj@X,Y` (no model: both
voxelize and paint it 1 mm deep over the white resin, on 0.5 mm voxels). In a block inside each
face's skin (0.2 to 0.6 mm deep: deeper, the resampling blends in the core; 2 mm by 2 mm about
the face's middle) the share of each resin's pixels
  - in the tray equals the layers stack's within 0.01, and
  - equals Pillow ImageCms's sRGB -> CMYK transform of the face's colour (the rule of
    hovox/colour.h) within 0.02 (blue-noise averaged over the block);
and the tray manifest's part carries "colour" (profile, skin voxels, dE2000) equal to layers'.
Usage: check_tray_colour.py HOVOX TMPDIR"""
import json
import os
import subprocess
import sys

from PIL import Image

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import check_paint  # noqa: E402  (the cube, the resins and the LittleCMS fractions)

SIZE, AT = 6.0, (40.0, 30.0)
check_paint.SIZE = SIZE


def face_box(axis, side):
    """(x0, x1, y0, y1, z0, z1) mm in the mesh's coordinates: the block in a face's skin."""
    box = [[SIZE / 2 - 1, SIZE / 2 + 1] for _ in range(3)]
    box[axis] = [SIZE - 0.6, SIZE - 0.2] if side else [0.2, 0.6]
    return [v for a in box for v in a]


def shares(stack, files, to_pixel, boxes, names, lh):
    """Per box, the share of each resin's pixels in it, its pixels and layers; to_pixel(x, y) gives
    (column, row) of the stack. Each layer is read once for all boxes."""
    counts = [[0] * 256 for _ in boxes]
    nlayers = [0] * len(boxes)
    spans = [range(int(b[4] / lh + 0.5), int(b[5] / lh + 0.5)) for b in boxes]
    for i in sorted(set(i for sp in spans for i in sp)):
        im = Image.open(os.path.join(stack, files(i)))
        for k, b in enumerate(boxes):
            if i not in spans[k]:
                continue
            c0, r0 = to_pixel(b[0], b[3])
            c1, r1 = to_pixel(b[1], b[2])
            counts[k] = [x + y for x, y in zip(counts[k], im.crop((c0, r0, c1, r1)).histogram())]
            nlayers[k] += 1
    out = []
    for c, n in zip(counts, nlayers):
        total = sum(c)
        if c[0]:
            sys.exit("%s: background inside a block (%d pixels)" % (stack, c[0]))
        out.append(({names[k]: v / total for k, v in enumerate(c) if k in names}, total, n))
    return out


def main():
    hovox, tmp = sys.argv[1], sys.argv[2]
    check_paint.write_cube(tmp)
    cube = os.path.join(tmp, "cube.obj")
    ls, ts = os.path.join(tmp, "layers"), os.path.join(tmp, "tray")
    run = lambda *a: subprocess.run([hovox] + list(a), check=True, capture_output=True, text=True)  # noqa: E731
    run("layers", cube, "--place", "%g,%g" % AT, "-o", ls, "-q")
    run("tray", "--part", "%s@%g,%g" % ((cube,) + AT), "-o", ts, "-q")
    lm = json.load(open(os.path.join(ls, "manifest.json")))
    tm = json.load(open(os.path.join(ts, "manifest.json")))
    lh = lm["layer_height_mm"]
    # the layers stack: pixel (c, r) has its centre at origin + (c + 0.5, r + 0.5) * pixel
    (ox, oy), (sx, sy) = lm["origin_mm"], lm["pixel_mm"]
    l_pixel = lambda x, y: (int(round((x - ox) / sx)), int(round((y - oy) / sy)))  # noqa: E731
    l_names = {m["palette_index"]: m["name"] for m in lm["materials"]}
    l_files = {layer["index"]: layer["file"] for layer in lm["layers"]}
    # the tray: the part's box centred at AT on the plate, rows running down from the plate's far edge
    part = tm["parts"][0]
    bx = part["box_mm"]
    dx, dy = (bx[0] + bx[2]) / 2 - SIZE / 2, (bx[1] + bx[3]) / 2 - SIZE / 2
    tsx, tsy = 25.4 / tm["dpi"][0], 25.4 / tm["dpi"][1]
    t_pixel = lambda x, y: (int(round((x + dx) / tsx)), int(round((tm["plate_mm"][1] - (y + dy)) / tsy)))  # noqa: E731
    t_names = {p["index"]: p["resin"] for p in tm["palette"] if p["resin"]}
    want = check_paint.littlecms()
    worst_pair = worst_cms = 0.0
    boxes = [face_box(axis, side) for _, _, axis, side, _ in check_paint.FACES]
    la = shares(ls, lambda i: l_files[i], l_pixel, boxes, l_names, lh)
    ta = shares(ts, lambda i: "layer-%05d.png" % i, t_pixel, boxes, t_names, lh)
    for face, w, (a, na, _), (b, nb, lb) in zip(check_paint.FACES, want, la, ta):
        if na != nb or na < 10000:
            sys.exit("face %s: blocks of %d and %d pixels" % (face[0], na, nb))
        for r, v in zip(check_paint.RESINS, w):
            worst_pair = max(worst_pair, abs(a.get(r, 0) - b.get(r, 0)))
            worst_cms = max(worst_cms, abs(b.get(r, 0) - v), abs(a.get(r, 0) - v))
        print("face %-3s %6d pixels in %d layers: tray %s" % (face[0], nb, lb,
              " ".join("%.3f" % b.get(r, 0) for r in check_paint.RESINS)))
    lc, tc = lm.get("colour"), part.get("colour")
    if not lc or not tc:
        sys.exit("colour missing from the manifests (layers %s, tray %s)" % (bool(lc), bool(tc)))
    for k in ("icc", "intent", "skin_voxels"):
        if lc[k] != tc[k]:
            sys.exit("manifest colour %s: layers %r, tray %r" % (k, lc[k], tc[k]))
    if abs(lc["mean_de2000_target"] - tc["mean_de2000_target"]) > 1e-9:
        sys.exit("manifest colour dE2000: layers %g, tray %g" % (lc["mean_de2000_target"], tc["mean_de2000_target"]))
    print("tray vs layers: worst %.4f (<= 0.01); vs Pillow ImageCms: worst %.4f (<= 0.02); skin %d voxels, "
          "mean dE2000 %.2f target, %.2f achieved in the tray" % (worst_pair, worst_cms, tc["skin_voxels"],
                                                                  tc["mean_de2000_target"],
                                                                  tc["mean_de2000_achieved"]))
    if worst_pair > 0.01 or worst_cms > 0.02:
        sys.exit(1)


if __name__ == "__main__":
    main()
