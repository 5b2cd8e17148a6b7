#!/usr/bin/python3
"""tests/colour/check_paint.py - a part painted in its colours, checked against an independent
LittleCMS caller (issue 29 checks): a 10 mm cube whose six faces carry six flat colours (OBJ + MTL
Kd) is voxelized at 0.25 mm and painted DEPTH mm deep over an Agilus30 core (`hovox voxelize
--colour-depth --core`), then
  - `hovox probe` at each face's centre one voxel in: the six fractions equal Pillow ImageCms's
    sRGB -> CMYK transform of that face's colour (same profile and intent), mixed by the rule of
    hovox/colour.h, within 0.01;
  - the depth: the voxel centred half a voxel inside DEPTH still has the colour, the one half a
    voxel beyond it is all core (the change is one voxel sharp);
  - `hovox layers` (J750, blue-noise halftone): in a block of 32 x 32 pixels x 32 layers inside
    each face's skin, the share of each resin's pixels is the face's fractions within 0.02.
Usage: check_paint.py HOVOX TMPDIR"""
import json
import os
import subprocess
import sys

from PIL import Image, ImageCms

FACES = [  # name, colour, the face's axis and side, its facet in the OBJ
    ("-z", (255, 0, 0), 2, 0, "f 1 4 3 2"),
    ("+z", (0, 255, 0), 2, 1, "f 5 6 7 8"),
    ("-y", (0, 0, 255), 1, 0, "f 1 2 6 5"),
    ("+x", (255, 255, 0), 0, 1, "f 2 3 7 6"),
    ("+y", (0, 255, 255), 1, 1, "f 3 4 8 7"),
    ("-x", (255, 0, 255), 0, 0, "f 4 1 5 8"),
]
SIZE, VOXEL, DEPTH = 10.0, 0.25, 3.0
ICC = "/usr/share/color/icc/ghostscript/default_cmyk.icc"
RESINS = ["VeroCyan-V", "VeroMagenta-V", "VeroYellow-V", "VeroBlackPlus", "VeroPureWhite", "VeroClear"]


def mix(cmyk):
    ink = [v / 255.0 for v in cmyk]
    t = sum(ink)
    return [v / t if t > 1 else v for v in ink] + [1 - t if t < 1 else 0, 0]


def littlecms():
    tr = ImageCms.buildTransform(ImageCms.createProfile("sRGB"), ImageCms.getOpenProfile(ICC), "RGB", "CMYK",
                                 renderingIntent=0)
    im = Image.new("RGB", (len(FACES), 1))
    im.putdata([f[1] for f in FACES])
    out = Image.new("CMYK", im.size)
    tr.transform.apply(im.im.id, out.im.id)
    return [mix(c) for c in out.getdata()]


def write_cube(d):
    with open(os.path.join(d, "cube.mtl"), "w") as f:
        for name, rgb, *_ in FACES:
            f.write("newmtl %s\nKd %g %g %g\n" % (name, rgb[0] / 255, rgb[1] / 255, rgb[2] / 255))
    with open(os.path.join(d, "cube.obj"), "w") as f:
        f.write("mtllib cube.mtl\n")
        for k in range(8):
            f.write("v %g %g %g\n" % (SIZE * (k in (1, 2, 5, 6)), SIZE * (k in (2, 3, 6, 7)), SIZE * (k >= 4)))
        for name, _, _, _, facet in FACES:
            f.write("usemtl %s\n%s\n" % (name, facet))


def point(axis, side, depth):
    p = [SIZE / 2] * 3
    p[axis] = SIZE - depth if side else depth
    return p


def probe(hovox, model, points):
    args = [",".join("%g" % v for v in p) for p in points]
    out = subprocess.run([hovox, "probe", model] + args, check=True, capture_output=True, text=True).stdout
    rows = [line.split(",") for line in out.strip().split("\n")]
    head = rows[0]
    return [{h: float(v) for h, v in zip(head, r)} for r in rows[1:]]


def check_probe(hovox, model, want):
    worst = 0.0
    inner = [point(a, s, VOXEL * 1.5) for _, _, a, s, _ in FACES]
    for face, row, w in zip(FACES, probe(hovox, model, inner), want):
        for r, v in zip(RESINS, w):
            worst = max(worst, abs(row.get(r, 0) - v))  # a resin that gave way (six slots) is absent
        if row["Agilus30"] != 0:
            sys.exit("face %s: core %g in the skin" % (face[0], row["Agilus30"]))
    if worst > 0.01:
        sys.exit("skin fractions differ from LittleCMS (Pillow) by %.4f > 0.01" % worst)
    # centres half a voxel either side of the depth
    near = [point(a, s, DEPTH - VOXEL / 2) for _, _, a, s, _ in FACES]
    far = [point(a, s, DEPTH + VOXEL / 2) for _, _, a, s, _ in FACES]
    for face, row in zip(FACES, probe(hovox, model, near)):
        if row["Agilus30"] != 0:
            sys.exit("face %s: %g mm deep (inside the depth) holds core %g" % (face[0], DEPTH - VOXEL / 2,
                                                                               row["Agilus30"]))
    for face, row in zip(FACES, probe(hovox, model, far)):
        if row["Agilus30"] != 1:
            sys.exit("face %s: %g mm deep (beyond the depth) holds core %g, not 1" % (face[0], DEPTH + VOXEL / 2,
                                                                                     row["Agilus30"]))
    return worst


def block_shares(stack, man, box):
    """Share of each material's pixels in box = (x0, x1, y0, y1, first layer, last layer)."""
    ox, oy = man["origin_mm"]
    px, py = man["pixel_mm"]
    c0 = min(int(round((box[0] - ox) / px)), int(round((box[1] - ox) / px)))
    r0 = min(int(round((box[2] - oy) / py)), int(round((box[3] - oy) / py)))
    c1, r1 = c0 + 32, r0 + 32
    counts = {}
    for layer in man["layers"]:
        if not box[4] <= layer["index"] < box[5]:
            continue
        im = Image.open(os.path.join(stack, layer["file"]))
        px_ = im.load()
        for r in range(r0, r1):
            for c in range(c0, c1):
                counts[px_[c, r]] = counts.get(px_[c, r], 0) + 1
    total = sum(counts.values())
    return {m["name"]: counts.get(m["palette_index"], 0) / total for m in man["materials"]}, total


def check_halftone(hovox, model, tmp, want):
    stack = os.path.join(tmp, "stack")
    lh = 0.027
    subprocess.run([hovox, "layers", model, "-o", stack, "-q"], check=True, capture_output=True)
    man = json.load(open(os.path.join(stack, "manifest.json")))
    worst = 0.0
    inset, span_x, span_y = 0.2, 32 * man["pixel_mm"][0], 32 * abs(man["pixel_mm"][1])
    nlayers = len(man["layers"])
    for (name, _, axis, side, _), w in zip(FACES, want):
        lo = [SIZE / 2 - span_x / 2, SIZE / 2 - span_y / 2, SIZE / 2]
        if axis == 0:
            lo[0] = SIZE - inset - span_x if side else inset
        elif axis == 1:
            lo[1] = SIZE - inset - span_y if side else inset
        z0 = int(lo[2] / lh) - 16
        if axis == 2:
            z0 = nlayers - int(inset / lh) - 32 if side else int(inset / lh)
        shares, total = block_shares(stack, man, (lo[0], lo[0] + span_x, lo[1] + span_y, lo[1], z0, z0 + 32))
        if total != 32 * 32 * 32:
            sys.exit("face %s: block of %d pixels, not 32768" % (name, total))
        for r, v in zip(RESINS, w):
            worst = max(worst, abs(shares.get(r, 0) - v))
        if shares.get("Agilus30", 0):
            sys.exit("face %s: core in the skin's block" % name)
    if worst > 0.02:
        sys.exit("blue-noise shares differ from LittleCMS (Pillow) by %.4f > 0.02" % worst)
    return worst


def main():
    hovox, tmp = sys.argv[1], sys.argv[2]
    write_cube(tmp)
    model = os.path.join(tmp, "cube.vdb")
    subprocess.run([hovox, "voxelize", os.path.join(tmp, "cube.obj"), "--voxel-size", str(VOXEL), "--colour-depth",
                    str(DEPTH), "--core", "Agilus30", "-o", model, "-q"], check=True, capture_output=True)
    want = littlecms()
    skin = check_probe(hovox, model, want)
    block = check_halftone(hovox, model, tmp, want)
    print("six faces: skin fractions within 0.01 of Pillow ImageCms, the core from %g mm (one voxel sharp), "
          "blue-noise 32^3 blocks within 0.02" % DEPTH)
    if skin > 0.01 or block > 0.02:
        sys.exit(1)


if __name__ == "__main__":
    main()
