# issue 16's multi-body case end to end from a 3MF: a Vero shell with a cavity and the Agilus
# core filling it (two objects with two base materials, tests/data/good/core_in_shell.3mf) voxelize
# to two regions with their materials, grade to them without sources, and the stack printed from
# the same 3MF as --mesh (contours per body, their union constraining the layers) holds both
# materials at mid-height: the core's (palette 2, 'A') inside the shell's (palette 1, 'V')
m=tests/data/good/core_in_shell.3mf
$HOVOX voxelize $m -o "$TMP/a.vdb" --voxel-size 0.5 -q &&
$HOVOX grade "$TMP/a.vdb" -o "$TMP/g.vdb" -q &&
$HOVOX layers "$TMP/g.vdb" --mesh $m -o "$TMP/stack" --dpi 50,50 --layer-height 1 -q &&
# the target is a mean of float fractions: its last digits follow the build's float contraction
# (the sanitizer build differs past the 8th), so it is shown to 7 decimals
sed -n '/"materials"/,/]/p' "$TMP/stack/manifest.json" | sed -E 's/("target": [0-9]+\.[0-9]{7})[0-9]*/\1/' &&
/usr/bin/python3 -c "
import zlib, struct, sys
d = open(sys.argv[1], 'rb').read()
w, h, bd, ct = struct.unpack('>IIBB', d[16:26])
pos = 8; idat = b''
while pos < len(d):
    n, = struct.unpack('>I', d[pos:pos+4]); t = d[pos+4:pos+8]
    if t == b'IDAT': idat += d[pos+8:pos+8+n]
    pos += 12 + n
raw = zlib.decompress(idat); stride = (w * bd + 7) // 8
count = [0, 0, 0, 0]
for y in range(h):
    row = raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)]
    px = [(row[x * bd // 8] >> (8 - bd - (x * bd) % 8)) & ((1 << bd) - 1) for x in range(w)]
    for v in px: count[v] += 1
    print(''.join('.VA?'[v] for v in px))
print('pixels per palette index', count)
" "$TMP/stack/layer-00005.png"
echo "rc=$?"
