#!/usr/bin/python3
"""tests/cli/png_palette_map.py PNG CHARS [--size] - a palette PNG of a slice stack as text: one
line per row, pixel value v printed as CHARS[v], then the pixel count per palette index. Reads
the PNG with zlib alone (not hovox's code). --size first prints the size, bit depth and colour
type."""
import struct
import sys
import zlib

path, chars = sys.argv[1], sys.argv[2]
d = open(path, 'rb').read()
w, h, bd, ct = struct.unpack('>IIBB', d[16:26])
pos = 8
idat = b''
while pos < len(d):
    n, = struct.unpack('>I', d[pos:pos + 4])
    if d[pos + 4:pos + 8] == b'IDAT':
        idat += d[pos + 8:pos + 8 + n]
    pos += 12 + n
raw = zlib.decompress(idat)
stride = (w * bd + 7) // 8
if '--size' in sys.argv[3:]:
    print('size', w, h, 'bit depth', bd, 'colour type', ct)
count = [0] * (1 << bd)
for y in range(h):
    row = raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)]
    px = [(row[x * bd // 8] >> (8 - bd - (x * bd) % 8)) & ((1 << bd) - 1) for x in range(w)]
    for v in px:
        count[v] += 1
    print(''.join(chars[v] for v in px))
print('pixels per palette index', count)
