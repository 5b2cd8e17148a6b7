#!/usr/bin/python3
"""tests/cli/png_palette_map.py PNG CHARS [--size] - a palette PNG of a slice stack as text: one
line per row, pixel value v printed as CHARS[v], then the pixel count per palette index. Reads
the PNG with zlib alone (tests/support/png_read.py, not hovox's code). --size first prints the
size, bit depth and colour type."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from png_read import pixels, read_png  # noqa: E402 (the tests' one PNG reader)

path, chars = sys.argv[1], sys.argv[2]
w, h, bd, ct, rows = read_png(path)
if '--size' in sys.argv[3:]:
    print('size', w, h, 'bit depth', bd, 'colour type', ct)
count = [0] * (1 << bd)
for row in rows:
    px = pixels(row, bd, 0, w)
    for v in px:
        count[v] += 1
    print(''.join(chars[v] for v in px))
print('pixels per palette index', count)
