# issue 28: a tray part from a model alone takes the shape the model records, as layers does: the
# plate 8 x 4 x 2 minus a rod of radius 1 (CSG subtract), as --part MODEL@X,Y and turned a quarter
# (--part MODEL@X,Y,90), and from a job file without "mesh". Every layer keeps the hole: the 1-bit
# mask of each part's box at 50 dpi, drawn (the first layer). A model that records no shape is
# refused naming the part, nothing written; so are the placement options, which move a mesh
here=$(pwd)
cd "$TMP" || exit 1
/usr/bin/python3 "$here/tests/cli/cases/holed_plate.py" 8,4,2 1 32 0.25 subtract holed.vdb || exit 1
$HOVOX tray --part holed.vdb@20,370 --part holed.vdb@40,370,90 -o tray --mode mask --resin A=VeroCyan-V \
    --resin B=VeroMagenta-V --layers 0:74; echo "rc=$?"
/usr/bin/python3 - "$here/tests/support" <<'PY'
import json, sys
sys.path.insert(0, sys.argv[1])
from png_read import pixel, read_png
m = json.load(open("tray/manifest.json"))
for p in m["parts"]:
    print(p["name"], "mesh", p["mesh"], "rotation", p["rotation"], "box_mm", p["box_mm"])
def layer(path):
    w, h, bd, ct, rows = read_png(path)
    return lambda x, y: pixel(rows, bd, x, y)
sx, py = 25.4 / 600, 25.4 / 300
holes = 0
for l in range(74):
    px = layer("tray/layer-%05d.png" % l)
    for p in m["parts"]:
        x0, y0, x1, y1 = p["box_mm"]
        # the centre of the part (the rod's axis) must be empty in every layer
        cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
        holes += px(int(cx / sx), int((390 - cy) / py)) != 0
    if l == 0:
        for p in m["parts"]:
            x0, y0, x1, y1 = p["box_mm"]
            for yy in [y1 - (k + 0.5) * 0.5 for k in range(int((y1 - y0) / 0.5))]:
                print("".join("#" if px(int(xx / sx), int((390 - yy) / py)) else "." for xx in [x0 + (k + 0.5) * 0.25 for k in range(int((x1 - x0) / 0.25))]))
            print()
print("object pixels at the rod's axis over 74 layers:", holes)
PY
printf '{"resin": {"A": "VeroCyan-V", "B": "VeroMagenta-V"}, "parts": [{"model": "holed.vdb", "at": [20, 370]},
 {"model": "holed.vdb", "at": [40, 370], "rotation": 90}]}\n' > j.json
$HOVOX tray j.json -o job --mode mask --layers 0:74; echo "rc=$?"
for l in 00000 00037 00073; do cmp -s tray/layer-$l.png job/layer-$l.png && echo "layer $l: the job's bytes"; done
cp $SHARED/models/ungraded.vdb old.vdb
$HOVOX tray --part old.vdb@20,370 -o refused --mode mask; echo "rc=$?"
$HOVOX tray --part holed.vdb@20,370 --scale 2 -o refused --mode mask --resin A=VeroCyan-V --resin B=VeroMagenta-V; echo "rc=$?"
ls refused 2>&1 | sed 's/.*: //'
