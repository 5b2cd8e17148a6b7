# issue 29 item 1: a tray's resin mapping is "a resin" for the body rule (hv_colour_mesh_bodies with
# the tray's is_resin). badge.3mf (tests/colour/colour_assembly.py, written by Python): a plate of
# Agilus30Black, a badge in a colour group's #C01010 on it, a grip of the base material "PLA Blue".
# Asked for colour (--colour-depth), the grip is painted in its displaycolor (layers_assembly_paint);
# mapped to a resin (--resin PLA_Blue=VeroCyan-V, a job file's "resin" object, Lua's resin = {...})
# it prints in that resin, every pixel of it, and only the badge is painted (3380 skin voxels, as
# unasked). A resin the tray adds by --resin-color is a resin too: kept beside the badge's five
# colour resins and the plate's, seven, more than the printer's six slots (one message, exit 1,
# nothing written). Layer 74 (z 2 mm: plate and grip) counted per palette entry by Pillow.
/usr/bin/python3 tests/colour/colour_assembly.py "$TMP" >/dev/null || exit 9
count() {
    /usr/bin/python3 - "$1" <<'PY'
import json, sys
from PIL import Image
m = json.load(open(sys.argv[1] + "/manifest.json"))
names = {e["index"]: e["resin"] for e in m["palette"]}
hist = Image.open(sys.argv[1] + "/layer-00074.png").histogram()
print(", ".join("%s %d" % (names[k], hist[k]) for k in sorted(names) if k and hist[k]),
      "| skin voxels", m["parts"][0]["colour"]["skin_voxels"],
      "|", ", ".join("%s->%s %.3f" % (k, v["resin"], v["target"]) for k, v in sorted(m["parts"][0]["materials"].items())
                     if v["target"]))
PY
}
cd "$TMP" || exit 9
$HOVOX tray --part badge.3mf@60,60 --colour-depth 1 -o painted --layers 74:75 -q; echo "rc=$?"
count painted
$HOVOX tray --part badge.3mf@60,60 --colour-depth 1 --resin PLA_Blue=VeroCyan-V -o mapped --layers 74:75 \
    | sed -n '/^plate/p;/^colour/p'
count mapped
cat >job.json <<'JOB'
{"schema": 1, "layers": "74:75", "resin": {"PLA_Blue": "VeroCyan-V"},
 "parts": [{"mesh": "badge.3mf", "at": [60, 60], "colour_depth": 1}]}
JOB
$HOVOX tray job.json -o job -q; echo "rc=$?"
cmp mapped/layer-00074.png job/layer-00074.png && echo "job file: the same layer"
cat >t.lua <<'LUA'
local t = hovox.tray{resin = {PLA_Blue = "VeroCyan-V"}}
t:add{mesh = "badge.3mf", at = {60, 60}, colour_depth = 1}
t:layers{dir = "lua", layers = {74, 75}}
LUA
$HOVOX run t.lua; echo "rc=$?"
cmp mapped/layer-00074.png lua/layer-00074.png && echo "Lua: the same layer"
$HOVOX tray --part badge.3mf@60,60 --colour-depth 1 --resin-color PLA_Blue=#2050c0 -o added --layers 74:75 -q
echo "rc=$?"
[ -e added ] || echo "nothing written"
