# hovox view on a halftone stack of a graded box (100 x 50 dpi: a pixel twice as tall as wide): the
# summary, the page inside the stack, what it carries (the layers by relative path, every row and 32
# columns as side views, the object's outline), and a page elsewhere reaching the stack by "../"
cd "$TMP"
"$HOVOX" generate box max=12,8,3 -o b.stl >/dev/null
"$HOVOX" voxelize b.stl --voxel-size 0.4 -o o.vdb -q >/dev/null
"$HOVOX" grade o.vdb -o g.vdb --materials A,B --frf plane:0,0,0:1,0,0 --ranges 0,12,0 --ms 1,0 --me 0,1 -q
"$HOVOX" layers g.vdb --mesh b.stl -o st --dpi 100,50 --layer-height 0.5 -q >/dev/null
"$HOVOX" view st >"$TMP/.o"
echo "rc=$?"
sed 's/([0-9.]* [KM]iB)/(SIZE)/' "$TMP/.o"
ls st | grep -v layer-
/usr/bin/python3 - <<'PY'
import json, re
html = open("st/index.html").read()
d = json.loads(re.search(r'<script type="application/json" id="hovox-data">(.*?)</script>', html, re.S).group(1))
print(d["kind"], d["mode"], d["width"], d["height"], d["pixel_mm"], repr(d["base"]), d["title"])
print(len(d["files"][0]), d["files"][0][0], d["z_mm"][:3])
rows = [c for c in d["cuts"] if c["axis"] == "row"]
cols = [c for c in d["cuts"] if c["axis"] == "col"]
print(len(rows), "row cuts", len(cols), "column cuts, step", d["cut_step"], "first", rows[0]["pos"], rows[0]["w"], rows[0]["h"])
print([p["name"] for p in d["palette"]], [m["name"] for m in d["materials"]])
print(len(d["parts"]), d["parts"][0]["name"], d["parts"][0]["box_px"], len(d["parts"][0]["outline"]), "loop",
      d["parts"][0]["outline"][0])
print("no network:", "http:" not in html and "https:" not in html.replace("https://", "") and "<link" not in html)
PY
mkdir pages
"$HOVOX" view st -o pages/st.html | sed 's/([0-9.]* [KM]iB)/(SIZE)/'
grep -o '"base": "[^"]*"' pages/st.html
