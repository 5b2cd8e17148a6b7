#!/usr/bin/python3
"""tests/io/scan/tray_vs_layers.py TRAY LAYERS - a scan's part on a tray against `hovox layers SCAN
--place X,Y` of the same scan (issue 30): for every layer of the LAYERS stack (a 1-bit mask placed
on the plate: its manifest's plate column and row), the tray layer of the same index holds a
material exactly at the mask's object pixels in that window (pixel-exact), and nothing of the part
falls outside the window. Prints the layers compared and the object pixels; exit 1 on a difference.
Reads the PNGs with zlib alone (not hovox's code)."""
import json
import struct
import sys
import zlib


def read_png(path):
    d = open(path, 'rb').read()
    w, h, bd, ct = struct.unpack('>IIBB', d[16:26])
    pos, idat = 8, b''
    while pos < len(d):
        n, = struct.unpack('>I', d[pos:pos + 4])
        if d[pos + 4:pos + 8] == b'IDAT':
            idat += d[pos + 8:pos + 8 + n]
        pos += 12 + n
    raw = zlib.decompress(idat)
    stride = (w * bd + 7) // 8
    rows = []
    for y in range(h):
        f = raw[y * (stride + 1)]
        row = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if f != 0:  # hovox writes filter 0 (none) for palette and 1-bit layers; undo the others anyway
            prev = rows[-1] if rows else bytearray(stride)
            bpp = max(1, bd // 8)
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
    return w, h, bd, rows


def pixels(row, bd, x0, n):
    per = 8 // bd
    mask = (1 << bd) - 1
    return [(row[x // per] >> (8 - bd - bd * (x % per))) & mask for x in range(x0, x0 + n)]


tray_dir, lay_dir = sys.argv[1], sys.argv[2]
tm = json.load(open(tray_dir + '/manifest.json'))
lm = json.load(open(lay_dir + '/manifest.json'))
c0, r0 = lm['plate']['column'], lm['plate']['row']
W, H = lm['width'], lm['height']
bad = 0
obj = 0
for L in lm['layers']:
    w, h, bd, mask = read_png(lay_dir + '/' + L['file'])
    tw, th, tbd, plate = read_png('%s/layer-%05d.png' % (tray_dir, L['index']))
    assert (w, h) == (W, H)
    for r in range(h):
        m = pixels(mask[r], bd, 0, w)
        t = [v != 0 for v in pixels(plate[r0 + r], tbd, c0, w)]
        obj += sum(m)
        if m != [int(v) for v in t]:
            bad += sum(1 for a, b in zip(m, t) if a != b)
    # the part's own image (the tray's image_px of the scan part) holds nothing outside the window
    for p in tm['parts']:
        if p.get('scan') != lm['model']:
            continue
        pc, pr, pw, ph = p['image_px']
        for r in range(pr, pr + ph):
            if r0 <= r < r0 + h:
                row = pixels(plate[r], tbd, pc, pw)
                bad += sum(1 for x, v in enumerate(row) if v and not (c0 <= pc + x < c0 + w))
            else:
                bad += sum(1 for v in pixels(plate[r], tbd, pc, pw) if v)
print('%d layers, %d object pixels, %d differ' % (len(lm['layers']), obj, bad))
sys.exit(1 if bad else 0)
