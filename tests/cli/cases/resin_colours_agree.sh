# One colour table (issue 32 item 18): a material named like a resin (case-insensitively, as a
# tray maps it) is shown in that resin's colour by layers, render and tray alike (layers and
# render used the default palette, tray the resin's colour); --colors still wins in the model.
cd "$TMP"
"$HOVOX" generate box max=12,8,1 -o g.stl >/dev/null
"$HOVOX" voxelize g.stl --voxel-size 0.4 -o o.vdb -q >/dev/null
"$HOVOX" grade o.vdb -o r.vdb --materials VeroCyan-V,veromagenta-v --frf plane:0,0,0:1,0,0 \
    --ranges 0,12,0 --ms 1,0 --me 0,1 -q
"$HOVOX" grade o.vdb -o c.vdb --materials VeroCyan-V --frf point:0,0,0 --ranges 0,0,0 --ms 1 --me 1 -q
"$HOVOX" layers r.vdb --mesh g.stl -o l --place 40,30 -q >/dev/null
"$HOVOX" tray -o t --part r.vdb,g.stl@40,30 -q >/dev/null
"$HOVOX" render c.vdb --surface --flat --view top --ortho --size 64,64 -o c.png -q >/dev/null
"$HOVOX" grade o.vdb -o k.vdb --materials VeroCyan-V --colors '#102030' --frf point:0,0,0 --ranges 0,0,0 \
    --ms 1 --me 1 -q
"$HOVOX" layers k.vdb --mesh g.stl -o k --place 40,30 -q >/dev/null
/usr/bin/python3 - <<'PY'
import json
from PIL import Image
lay = json.load(open("l/manifest.json"))
print("layers", [(m["name"], m["color"]) for m in lay["materials"]])
tray = json.load(open("t/manifest.json"))
print("tray  ", [(p["resin"], p["color"]) for p in tray["palette"][1:]])
im = Image.open("c.png").convert("RGB")
print("render", "#%02x%02x%02x" % im.getpixel((32, 32)))
print("given ", [(m["name"], m["color"]) for m in json.load(open("k/manifest.json"))["materials"]])
PY
