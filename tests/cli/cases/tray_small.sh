# A reduced tray end to end (issue 14): two graded boxes (one turned a quarter) placed, a plain
# box in a resin, two arranged copies; the plan, the stack, its manifest's parts, and the same
# layers again from a job file with paths relative to it.
cd "$TMP"
"$HOVOX" generate box max=12,8,1 -o g.stl >/dev/null
"$HOVOX" voxelize g.stl --voxel-size 0.4 -o o.vdb -q >/dev/null
"$HOVOX" grade o.vdb -o g.vdb --materials A,B --frf plane:0,0,0:1,0,0 --ranges 0,12,0 --ms 1,0 --me 0,1 -q
"$HOVOX" generate box max=6,6,0.5 -o p.stl >/dev/null
"$HOVOX" tray -o stack --part g.vdb,g.stl@40,30 --part g.vdb,g.stl@70,30,90 --part p.stl:VeroPureWhitex2 \
    --arrange yes --resin A=VeroCyan-V --resin B=VeroMagenta-V --dry-run
echo "rc=$?"
"$HOVOX" tray -o stack --part g.vdb,g.stl@40,30 --part g.vdb,g.stl@70,30,90 --part p.stl:VeroPureWhitex2 \
    --arrange yes --resin A=VeroCyan-V --resin B=VeroMagenta-V --threads 2
echo "rc=$?"
ls stack | wc -l
/usr/bin/python3 - <<'PY'
import json
m = json.load(open("stack/manifest.json"))
print(m["kind"], m["width"], m["height"], m["bit_depth"], m["layers_total"], [p["resin"] for p in m["palette"]])
for p in m["parts"]:
    print(p["name"], p["copy"], p["at_mm"], p["rotation"], p["image_px"], sorted(p["materials"]))
PY
mkdir jobs && cat >jobs/job.json <<'JSON'
{"schema": 1, "resin": {"A": "VeroCyan-V", "B": "VeroMagenta-V"}, "arrange": "yes",
 "parts": [{"model": "../g.vdb", "mesh": "../g.stl", "at": [40, 30]},
           {"model": "../g.vdb", "mesh": "../g.stl", "at": [70, 30], "rotation": 90},
           {"mesh": "../p.stl", "material": "VeroPureWhite", "copies": 2}]}
JSON
"$HOVOX" tray jobs/job.json -o stack2 --layers 10:14 --gcvf stack2.zip
echo "rc=$?"
unzip -tq stack2.zip | sed "s|$TMP/||"
unzip -l stack2.zip | awk 'NR > 3 && $4 != "" { print $4 }' | head -6
for i in 10 11 12 13; do cmp -s stack/layer-000$i.png stack2/layer-000$i.png && echo "layer $i same"; done
