# hovox view on a model: slices along x, y and z and four renders, next to the model by default
cd "$TMP"
"$HOVOX" generate box max=12,8,3 -o b.stl >/dev/null
"$HOVOX" voxelize b.stl --voxel-size 0.4 -o o.vdb -q >/dev/null
"$HOVOX" grade o.vdb -o g.vdb --materials A,B --colors '#ff0000,#0000ff' --frf plane:0,0,0:1,0,0 --ranges 0,12,0 \
    --ms 1,0 --me 0,1 -q
"$HOVOX" view g.vdb --size 96,72 >"$TMP/.o"
echo "rc=$?"
sed 's/([0-9.]* [KM]iB)/(SIZE)/' "$TMP/.o"
/usr/bin/python3 - <<'PY'
import json, re
html = open("g.html").read()
d = json.loads(re.search(r'<script type="application/json" id="hovox-data">(.*?)</script>', html, re.S).group(1))
print(d["kind"], d["title"], d["dims"], d["voxel_mm"], d["origin_mm"], d["occupied"], d["step"])
print([(m["name"], m["color"], round(m["mean"], 3)) for m in d["materials"]])
print([(a["axis"], len(a["slices"]), a["w"], a["h"], len(a["images"])) for a in d["axes"]])
print([(r["name"], r["w"], r["h"]) for r in d["renders"]])
PY
"$HOVOX" view g.vdb -o small.html --no-renders --max-samples 20000 | sed 's/([0-9.]* [KM]iB)/(SIZE)/'
