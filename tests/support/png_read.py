"""tests/support/png_read.py - the test scripts' one PNG reader (grey and palette PNGs of 1, 2, 4 or
8 bits, as slice stacks are written), with zlib alone: not hovox's code, so a test of hovox's
PNGs does not read them with the writer it checks. Every filter type is undone (hovox writes
filter 0 for palette and 1-bit layers; libdeflate's path may choose others).
    import sys; sys.path.insert(0, "<repository>/tests/support"); from png_read import read_png
"""
import struct
import zlib


def read_png(path):
    """(width, height, bit depth, colour type, rows): rows a list of bytearrays, one per row,
    filters undone."""
    d = open(path, "rb").read()
    if d[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("%s: not a PNG" % path)
    w, h, bd, ct = struct.unpack(">IIBB", d[16:26])
    pos, idat = 8, b""
    while pos < len(d):
        n, = struct.unpack(">I", d[pos:pos + 4])
        if d[pos + 4:pos + 8] == b"IDAT":
            idat += d[pos + 8:pos + 8 + n]
        pos += 12 + n
    raw = zlib.decompress(idat)
    stride = (w * bd + 7) // 8
    bpp = max(1, bd // 8)
    rows = []
    for y in range(h):
        f = raw[y * (stride + 1)]
        row = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if f != 0:
            prev = rows[-1] if rows else bytearray(stride)
            for i in range(stride):
                a = row[i - bpp] if i >= bpp else 0
                b = prev[i]
                c = prev[i - bpp] if i >= bpp else 0
                if f == 1:
                    row[i] = (row[i] + a) & 255
                elif f == 2:
                    row[i] = (row[i] + b) & 255
                elif f == 3:
                    row[i] = (row[i] + (a + b) // 2) & 255
                else:
                    p = a + b - c
                    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                    row[i] = (row[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(row)
    return w, h, bd, ct, rows


def pixels(row, bd, x0, n):
    """The n values of a row (from read_png) from column x0 on."""
    per = 8 // bd
    mask = (1 << bd) - 1
    return [(row[x // per] >> (8 - bd - bd * (x % per))) & mask for x in range(x0, x0 + n)]


def pixel(rows, bd, x, y):
    """The value at column x, row y."""
    return (rows[y][x * bd // 8] >> (8 - bd - x * bd % 8)) & ((1 << bd) - 1)
