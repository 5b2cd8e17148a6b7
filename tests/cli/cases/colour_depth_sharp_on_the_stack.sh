# issue 29 item 3 (part): the colour depth is sharp on the stack, per printer pixel. The six-colour
# cube (4 mm) painted 1 mm deep over Agilus30Clear on three voxel sizes: the J750's pitch
# (0.0847 mm), 0.25 mm (`voxelize --voxel-size 0.25`) and 0.5 mm (`layers cube.obj --colour-depth
# 1` in one step: voxels of half the depth). Layer 74 (mid-height: the side faces) and layers
# 100 to 122 (z 2.71 to 3.31 mm: the top face's depth at z 3 mm, layer height 0.027 mm). Every
# object pixel whose centre lies deeper than the depth plus one printer voxel (0.0847 mm; its
# distance to the nearest of the six faces, from the manifest's pixel grid and z) prints the core,
# and every one shallower than the depth less one printer voxel prints a colour resin, never the
# core. The stack puts the change at the depth bilinear in the model's colour.depth grid (exact where
# the nearest face is one plane); at the core's edges (two faces within a voxel of equally near,
# the depth within a voxel) the distance has a crease that interpolation rounds off: there a pixel
# may be off, by at most a third of a voxel. Before the colour.depth grid the change was spread
# over a model voxel: +-0.25 / +-0.5 mm on the coarse voxels.
/usr/bin/python3 -c "
import sys; sys.path.insert(0, 'tests/colour'); import check_paint
check_paint.SIZE = 4; check_paint.write_cube(sys.argv[1])" "$TMP"
cd "$TMP"
"$HOVOX" voxelize cube.obj --voxel-size 0.0846667 --colour-depth 1 --core Agilus30Clear -o fine.vdb -q >/dev/null
"$HOVOX" voxelize cube.obj --voxel-size 0.25 --colour-depth 1 --core Agilus30Clear -o quarter.vdb -q >/dev/null
rc=0
for w in 74:75 100:123; do
    "$HOVOX" layers fine.vdb -o "fine-$w" --layers $w -q >/dev/null || rc=1
    "$HOVOX" layers quarter.vdb -o "quarter-$w" --layers $w -q >/dev/null || rc=1
    "$HOVOX" layers cube.obj --colour-depth 1 --core Agilus30Clear -o "half-$w" --layers $w -q >/dev/null || rc=1
done
echo "rc=$rc"
/usr/bin/python3 - <<'PY'
import json
from PIL import Image
size, depth, tol = 4.0, 1.0, 0.0846667
fail = 0
for name, h in (("fine", 0.0846667), ("quarter", 0.25), ("half", 0.5)):
    n = {"core": 0, "colour": 0, "edge": 0, "off": 0, "edge_off": 0}
    worst = 0.0
    for w in ("74:75", "100:123"):
        st = "%s-%s/" % (name, w)
        m = json.load(open(st + "manifest.json"))
        (ox, oy), (sx, sy) = m["origin_mm"], m["pixel_mm"]
        core = [x["palette_index"] for x in m["materials"] if x["name"] == "Agilus30Clear"][0]
        for layer in m["layers"]:
            im = Image.open(st + layer["file"])
            px, z = im.load(), layer["z_mm"]
            for r in range(im.height):
                for c in range(im.width):
                    v = px[c, r]
                    if v == 0:
                        continue
                    x, y = ox + (c + 0.5) * sx, oy + (r + 0.5) * sy
                    f = sorted([x, size - x, y, size - y, z, size - z])
                    d = f[0]
                    if abs(d - depth) <= tol:
                        continue
                    off = (v != core) if d > depth else (v == core)
                    if f[1] - f[0] < h and abs(d - depth) < h:
                        n["edge"] += 1
                        n["edge_off"] += off
                        if off:
                            worst = max(worst, abs(d - depth) / h)
                    else:
                        n["core" if d > depth else "colour"] += 1
                        n["off"] += off
    print("%-7s voxels %.4g mm: %d pixels deeper than the depth + 1 printer voxel, %d shallower than the depth - 1; "
          "%d of them off; at the core's edges %d, %d off (worst %.2f voxel)"
          % (name, h, n["core"], n["colour"], n["off"], n["edge"], n["edge_off"], worst))
    fail |= n["off"] > 0 or worst > 1 / 3 or n["core"] < 500 or n["colour"] < 1000
raise SystemExit(1 if fail else 0)
PY
echo "rc=$?"
