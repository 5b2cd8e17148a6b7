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
/usr/bin/python3 - "$TMP/s" <<'PY'
import json, struct, sys, zlib
d = sys.argv[1]
man = json.load(open(d + "/manifest.json"))
names = [m["name"] for m in man["materials"]]
data = open(d + "/layer-00111.png", "rb").read()
pos, idat, w, h, depth = 8, b"", 0, 0, 0
while pos < len(data):
    n, kind = struct.unpack(">I4s", data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    if kind == b"IHDR":
        w, h, depth = struct.unpack(">IIB", body[:9])
    elif kind == b"IDAT":
        idat += body
    pos += 12 + n
raw, stride, counts, prev = zlib.decompress(idat), (w * depth + 7) // 8, {}, bytearray((w * depth + 7) // 8)
for r in range(h):  # unfilter (bpp 1) and count the palette entries
    f, line = raw[r * (stride + 1)], bytearray(raw[r * (stride + 1) + 1:(r + 1) * (stride + 1)])
    for i in range(stride):
        a, b = line[i - 1] if i else 0, prev[i]
        c = prev[i - 1] if i else 0
        p = a + b - c
        pred = [0, a, b, (a + b) // 2, a if abs(p - a) <= abs(p - b) and abs(p - a) <= abs(p - c) else (b if abs(p - b) <= abs(p - c) else c)][f]
        line[i] = (line[i] + pred) & 255
    for x in range(w):
        v = (line[x * depth // 8] >> (8 - depth - (x * depth) % 8)) & ((1 << depth) - 1)
        counts[v] = counts.get(v, 0) + 1
    prev = line
obj = sum(c for v, c in counts.items() if v)
print("layer 111:", ", ".join("%s %.2f" % (names[v - 1], counts[v] / obj) for v in sorted(counts) if v))
PY
