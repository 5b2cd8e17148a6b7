# an assembly (an Agilus core in a Vero shell, made by a Lua script, see grade_assembly) graded to
# its bodies' materials, printed at 50 dpi with 1 mm layers: the layer at mid-height holds both
# materials, the core's (palette 1, 'A') inside the shell's (palette 2, 'V'). The mesh given is the
# assembly's geometry as one STL body; Lua prints it from the multi-body mesh itself
# (tests/lua/test_assembly.lua), and the OBJ (assembly.obj) once hovox reads OBJ.
$HOVOX run tests/lua/scripts/assembly.lua "$TMP" &&
$HOVOX grade "$TMP/assembly.vdb" -o "$TMP/g.vdb" -q &&
$HOVOX layers "$TMP/g.vdb" --mesh "$TMP/assembly.stl" -o "$TMP/stack" --dpi 50,50 --layer-height 1 -q &&
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
print('size', w, h, 'bit depth', bd, 'colour type', ct)
count = [0, 0, 0, 0]
for y in range(h):
    row = raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)]
    px = [(row[x * bd // 8] >> (8 - bd - (x * bd) % 8)) & ((1 << bd) - 1) for x in range(w)]
    for v in px: count[v] += 1
    print(''.join('.AV?'[v] for v in px))
print('pixels per palette index', count)
" "$TMP/stack/layer-00005.png"
