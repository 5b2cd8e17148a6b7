# issue 29 item 3 (part): the colour depth is sharp on the stack. The six-colour cube (4 mm)
# painted 1 mm deep over Agilus30Clear on voxels of the J750's pitch (0.0847 mm), its layer at
# mid-height: every object pixel whose centre lies deeper than the depth plus one voxel (its
# distance to the nearest side face, from the manifest's pixel grid) prints the core, and every
# one shallower than the depth less one voxel prints a colour resin, never the core. (The
# change is one model voxel wide: the stack interpolates the voxels; a per-pixel depth from the
# mesh is not done.)
/usr/bin/python3 -c "
import sys; sys.path.insert(0, 'tests/colour'); import check_paint
check_paint.SIZE = 4; check_paint.write_cube(sys.argv[1])" "$TMP"
cd "$TMP"
"$HOVOX" voxelize cube.obj --voxel-size 0.0846667 --colour-depth 1 --core Agilus30Clear -o c.vdb -q >/dev/null
"$HOVOX" layers c.vdb -o st --layers 74:75 -q >/dev/null
echo "rc=$?"
/usr/bin/python3 - <<'PY'
import json
from PIL import Image
m = json.load(open("st/manifest.json"))
(ox, oy), (sx, sy) = m["origin_mm"], m["pixel_mm"]
core = [x["palette_index"] for x in m["materials"] if x["name"] == "Agilus30Clear"][0]
im = Image.open("st/" + m["layers"][0]["file"])
px = im.load()
voxel, depth, size = 0.0846667, 1.0, 4.0
bad_deep = bad_skin = deep = skin = band = 0
for r in range(im.height):
    for c in range(im.width):
        v = px[c, r]
        if v == 0:
            continue
        x, y = ox + (c + 0.5) * sx, oy + (r + 0.5) * sy
        d = min(x, size - x, y, size - y)
        if d > depth + voxel:
            deep += 1
            bad_deep += v != core
        elif d < depth - voxel:
            skin += 1
            bad_skin += v == core
        else:
            band += 1
print("deeper than depth + 1 voxel: %d pixels, %d not core" % (deep, bad_deep))
print("shallower than depth - 1 voxel: %d pixels, %d core" % (skin, bad_skin))
print("within one voxel of the depth: %d pixels" % band)
raise SystemExit(1 if bad_deep or bad_skin or deep < 500 or skin < 1000 else 0)
PY
echo "rc=$?"
