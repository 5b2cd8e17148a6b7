# issue 27 item 4: a package as a slicer writes it (tests/data/good/slicer_assembly.3mf: metadata,
# Production UUIDs, a thumbnail; a textured VeroWhite plate without a default pid, a composite
# core of 0.3 VeroWhite + 0.7 Agilus30 placed by a component transform, two Agilus30 pegs in a
# component object turned 90 degrees by the assembly holding them, the assembly one build item)
# to a J750 stack in one command: info lists a body per mesh object the item places, each in its
# own material; layer 111 (z 3.01 mm) holds the core's mixture and the two pegs: VeroWhite is
# 0.3 x 64 mm^2 of the 72 mm^2 cut (0.267), printed 0.27.
m=tests/data/good/slicer_assembly.3mf
$HOVOX info $m 2>/dev/null | sed -n '/^build items/,$p'
$HOVOX layers $m -o "$TMP/s" | grep -v '^memory'
echo "rc=$?"
/usr/bin/python3 - "$TMP/s" tests/support <<'PY'
import json, sys
sys.path.insert(0, sys.argv[2])
from png_read import pixels, read_png
d = sys.argv[1]
man = json.load(open(d + "/manifest.json"))
names = [m["name"] for m in man["materials"]]
w, h, depth, ct, rows = read_png(d + "/layer-00111.png")
counts = {}
for line in rows:  # count the palette entries
    for v in pixels(line, depth, 0, w):
        counts[v] = counts.get(v, 0) + 1
obj = sum(c for v, c in counts.items() if v)
print("layer 111:", ", ".join("%s %.2f" % (names[v - 1], counts[v] / obj) for v in sorted(counts) if v))
PY
