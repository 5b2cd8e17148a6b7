# a tray written with --view: the page inside the stack names every part with its fractions;
# --force replaces a stack that holds its page
cd "$TMP"
"$HOVOX" generate box max=12,8,1 -o g.stl >/dev/null
"$HOVOX" voxelize g.stl --voxel-size 0.4 -o o.vdb -q >/dev/null
"$HOVOX" grade o.vdb -o g.vdb --materials A,B --frf plane:0,0,0:1,0,0 --ranges 0,12,0 --ms 1,0 --me 0,1 -q
"$HOVOX" generate box max=6,6,0.5 -o p.stl >/dev/null
"$HOVOX" tray -o t --part g.vdb,g.stl@40,30 --part p.stl:VeroPureWhitex2 --arrange yes --resin A=VeroCyan-V \
    --resin B=VeroMagenta-V --layers 0:4 --view >"$TMP/.o"
echo "rc=$?"
sed 's/([0-9.]* [KM]iB)/(SIZE)/' "$TMP/.o"
/usr/bin/python3 - <<'PY'
import json, re
html = open("t/index.html").read()
d = json.loads(re.search(r'<script type="application/json" id="hovox-data">(.*?)</script>', html, re.S).group(1))
print(d["kind"], d["width"], d["height"], len(d["files"][0]), d["files"][0][-1], d["title"])
print([(p["index"], p["name"], p["color"]) for p in d["palette"]])
for p in d["parts"]:
    mats = {k: (round(v.get("target", -1), 4), round(v.get("achieved", -1), 4)) for k, v in p["info"]["materials"].items()}
    print(p["name"], p["copy"], p["box_px"], p["layers"], mats, len(p["outline"]), "outline",
          len([c for c in d["cuts"] if c["part"] == d["parts"].index(p)]), "cuts")
PY
"$HOVOX" tray -o t --part p.stl:VeroPureWhite@20,20 --layers 0:2 --force -q >/dev/null
echo "rc=$?"
ls t
