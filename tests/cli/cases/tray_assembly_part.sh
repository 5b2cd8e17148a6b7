# issue 27 item 2: a tray part given as a mesh alone (--part MESH@X,Y, a job file's part with only
# "mesh") is the whole build in its bodies' materials, its model made in memory: core_in_shell.3mf
# (a VeroWhite shell, its Agilus30 core, 10 mm) at mid-height prints about 16% Agilus (the core's
# 4 x 4 mm in 10 x 10 mm). A body without a material is refused naming it (exit 1, nothing written).
m=tests/data/good/core_in_shell.3mf
$HOVOX tray -o "$TMP/t" --part $m@40,40 --resin VeroWhite=VeroPureWhite --resin Agilus30=Agilus30Black \
    --layers 185:186 | grep -v '^memory'
echo "rc=$?"
/usr/bin/python3 - "$TMP/t/manifest.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
for p in m["parts"]:
    print(p["name"], p["at_mm"], p["box_mm"])
    for k, v in p["materials"].items():
        print(" ", k, v["resin"], "%.2f" % v["achieved"])
PY
printf 'v 0 0 0\nv 4 0 0\nv 0 4 0\nv 0 0 4\no tip\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$TMP/tet.obj"
printf '{"parts": [{"mesh": "tet.obj", "at": [40, 40]}]}\n' >"$TMP/job.json"
$HOVOX tray "$TMP/job.json" -o "$TMP/none"
echo "rc=$?"
ls "$TMP"
# a --part whose mesh is under 1 mm is warned about naming the likely unit, as voxelize warns
$HOVOX generate box min=0,0,0 max=0.2,0.1,0.05 -o "$TMP/tiny.stl" >/dev/null
$HOVOX tray -o "$TMP/tt" --part "$TMP/tiny.stl:VeroPureWhite@40,40" --dry-run >/dev/null
echo "rc=$?"
