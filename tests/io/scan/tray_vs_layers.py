#!/usr/bin/python3
"""tests/io/scan/tray_vs_layers.py TRAY LAYERS - a scan's part on a tray against `hovox layers SCAN
--place X,Y` of the same scan (issue 30): for every layer of the LAYERS stack (a 1-bit mask placed
on the plate: its manifest's plate column and row), the tray layer of the same index holds a
material exactly at the mask's object pixels in that window (pixel-exact), and nothing of the part
falls outside the window. Prints the layers compared and the object pixels; exit 1 on a difference.
Reads the PNGs with zlib alone (not hovox's code)."""
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from png_read import pixels, read_png  # noqa: E402 (the tests' one PNG reader)

tray_dir, lay_dir = sys.argv[1], sys.argv[2]
tm = json.load(open(tray_dir + '/manifest.json'))
lm = json.load(open(lay_dir + '/manifest.json'))
c0, r0 = lm['plate']['column'], lm['plate']['row']
W, H = lm['width'], lm['height']
bad = 0
obj = 0
for L in lm['layers']:
    w, h, bd, _, mask = read_png(lay_dir + '/' + L['file'])
    tw, th, tbd, _, plate = read_png('%s/layer-%05d.png' % (tray_dir, L['index']))
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
