# issue 28: `export MODEL -o PART.3mf` writes the shape as a 3MF core package (what slicers read),
# the same surface as .stl: a plate 8 x 4 x 2 and a rod of radius 1 through it in material B, Wu's
# difference (the plate's shape, B where the rod was). hovox info reads the package: one object,
# closed, the .stl's facets, bounding box and volume; the materials A and B as base materials, the
# triangles B only on the top and bottom faces inside the rod's circle (1.5 voxels of slack: the
# material boundary is the voxels'). Lua writes the same bytes; --volumetric gives the Volumetric
# package of the voxels as before
here=$(pwd)
cd "$TMP" || exit 1
/usr/bin/python3 "$here/tests/cli/cases/holed_plate.py" 8,4,2 1 32 0.25 difference wd.vdb || exit 1
$HOVOX export wd.vdb -o wd.3mf > report.txt; echo "rc=$?"; sed -E "s/\([0-9]+ bytes\)/(N bytes)/" report.txt
$HOVOX export wd.vdb -o wd.stl -q >/dev/null || exit 1
$HOVOX info wd.3mf > 3mf.txt && $HOVOX info wd.stl > stl.txt || exit 1
grep -E "^(format|facets|bbox|volume|open edges|non-manifold|closed|materials|  [AB] )" 3mf.txt
for k in facets "bbox min" "bbox max" volume; do
    [ "$(grep "^$k " 3mf.txt)" = "$(grep "^$k " stl.txt)" ] && echo "$k: as the .stl"
done
/usr/bin/python3 - <<'PY'
import math, re, zipfile
x = zipfile.ZipFile("wd.3mf").read("3D/3dmodel.model").decode()
print(re.search(r'<object [^>]*>', x).group(0))
v = [tuple(float(a) for a in m) for m in re.findall(r'<vertex x="([^"]+)" y="([^"]+)" z="([^"]+)"', x)]
wrong = b = 0
for t in re.finditer(r'<triangle v1="(\d+)" v2="(\d+)" v3="(\d+)"( pid="1" p1="(\d)")?', x):
    c = [sum(v[int(t.group(i))][a] for i in (1, 2, 3)) / 3 for a in range(3)]
    d, cap, mat = math.hypot(c[0] - 4, c[1] - 2), abs(c[2]) < 1e-3 or abs(c[2] - 2) < 1e-3, int(t.group(5) or 0)
    b += mat == 1
    wrong += (mat != 1) if cap and d < 1 - 0.375 else (mat != 0) if (d > 1.375 or not cap) else 0
print("triangles in B: %s, in the wrong material: %d" % ("some" if b else "none", wrong))
PY
echo 'hovox.load("wd.vdb"):export{path = "lua.3mf"}' > e.lua && $HOVOX run e.lua && cmp wd.3mf lua.3mf && echo "Lua: the same bytes"
$HOVOX export wd.vdb -o vol.3mf --volumetric | grep -E "^(mesh|images)"
