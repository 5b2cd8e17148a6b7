# a 10 x 6 x 4 mm box in mask mode at 50 dpi (0.508 mm pixels), 1 mm layers: 20 x 12 object
# pixels (centres in [0, 10) x [0, 6)) inside a 2-pixel margin, 4 layers cut at z = 0.5 ... 3.5
$HOVOX generate box sx=10 sy=6 sz=4 -o "$TMP/b.stl" &&
$HOVOX layers --mesh "$TMP/b.stl" -o "$TMP/stack" --mode mask --dpi 50,50 --layer-height 1 &&
ls "$TMP/stack" && cat "$TMP/stack/manifest.json" &&
/usr/bin/python3 -c "
import zlib, struct, sys
d = open(sys.argv[1], 'rb').read()
ihdr = d[16:29]; w, h, bd, ct = struct.unpack('>IIBB', ihdr[:10])
pos = 8; idat = b''
while pos < len(d):
    n, = struct.unpack('>I', d[pos:pos+4]); t = d[pos+4:pos+8]
    if t == b'IDAT': idat += d[pos+8:pos+8+n]
    if t == b'pHYs': print('pHYs', struct.unpack('>IIB', d[pos+8:pos+17]))
    pos += 12 + n
raw = zlib.decompress(idat); stride = (w * bd + 7) // 8
print('size', w, h, 'bit depth', bd, 'colour type', ct)
for y in range(h):
    row = raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)]
    assert raw[y * (stride + 1)] == 0
    print(''.join('#' if (row[x // 8] >> (7 - x % 8)) & 1 else '.' for x in range(w)))
" "$TMP/stack/layer-00001.png"
