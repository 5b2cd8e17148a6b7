# (the memory plan: --max-memory refuses, nothing written)
# issue 28: export .stl of a Boolean: the plate 40 x 20 x 10 minus a 10 mm rod through it as a
# level set per mesh, OpenVDB CSG, volumeToMesh: bbox within 0.05 mm of 0..40 x 0..20 x 0..10,
# volume within 0.5% of 8000 - 250 pi (hovox info and admesh as oracles), every edge shared by two
# facets, one part; Lua's model:export gives the same bytes
here=$(pwd)
cd "$TMP" || exit 1
/usr/bin/python3 "$here/tests/cli/cases/holed_plate.py" 40,20,10 5 64 0.25 subtract holed.vdb || exit 1
$HOVOX export holed.vdb -o holed.stl --dry-run; echo "rc=$?"
$HOVOX export holed.vdb -o holed.stl -q >/dev/null; echo "rc=$?"
$HOVOX info holed.stl > info.txt
grep -E "^(open edges|non-manifold|flipped|shells|closed)" info.txt
/usr/bin/python3 - <<'PY'
import math
f = dict(l.split(None, 1) if not l.startswith(("bbox", "open", "non-", "degenerate", "flipped", "normal")) else (l[:20].strip(), l[20:]) for l in open("info.txt") if l.strip())
lo = [float(x) for x in f["bbox min"].split()]; hi = [float(x) for x in f["bbox max"].split()]
ok = all(abs(a) <= 0.05 for a in lo) and all(abs(a - b) <= 0.05 for a, b in zip(hi, (40, 20, 10)))
print("bbox within 0.05 mm of 0..40 x 0..20 x 0..10:", ok)
v, want = float(f["volume"]), 8000 - 250 * math.pi
print("volume within 0.5%% of 8000 - 250 pi: %s (%.2f%%)" % (abs(v - want) <= 0.005 * want, 100 * (v - want) / want))
PY
admesh holed.stl | grep -E "disconnected|Number of parts" | sed 's/  *Volume.*//'
echo 'hovox.load("holed.vdb"):export{path = "lua.stl"}' > e.lua && $HOVOX run e.lua && cmp holed.stl lua.stl && echo "Lua: the same bytes"
# the level sets are planned: over --max-memory, refused before the work, nothing written
$HOVOX export holed.vdb -o small.stl --max-memory 16M; echo "rc=$?"
ls small.stl 2>&1 | sed 's/.*: //'
