#!/usr/bin/python3
"""tests/io/scan/stack_iou.py - a mask stack printed from the scan phantom (make_phantom.py) against the
analytic ellipsoid rasterised at the same pixel centres and layer heights (issue 30's check: IoU >=
0.995). Reads DIR/manifest.json and the 1-bit layers with Pillow; prints the IoU and exits 1 below
the bound given.

    stack_iou.py DIR [--min 0.995] [--scale 1.0]
"""
import argparse
import json
import os
import sys

import numpy as np
from PIL import Image

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_phantom import AXES, CENTRE  # noqa: E402  (the phantom's one definition)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('dir')
    ap.add_argument('--min', type=float, default=0.995)
    ap.add_argument('--scale', type=float, default=1.0, help='the shell: 1 skin (the head), 0.9 skull, 0.8 brain')
    a = ap.parse_args()
    m = json.load(open(os.path.join(a.dir, 'manifest.json')))
    sx, sy = m['pixel_mm']
    x0, y0 = m['origin_mm']
    w, h = m['width'], m['height']
    xs = x0 + (np.arange(w) + 0.5) * sx
    ys = y0 + (np.arange(h) + 0.5) * sy
    X, Y = np.meshgrid(xs, ys)
    inter = union = 0
    ax = AXES * a.scale
    for layer in m['layers']:
        z = layer['z_mm']
        got = np.array(Image.open(os.path.join(a.dir, layer['file'])).convert('L')) > 0
        q = ((X - CENTRE[0]) / ax[0]) ** 2 + ((Y - CENTRE[1]) / ax[1]) ** 2 + ((z - CENTRE[2]) / ax[2]) ** 2
        want = q <= 1
        inter += int((got & want).sum())
        union += int((got | want).sum())
    # the analytic part above the top layer or below the first is not printed: count whole layers only
    iou = inter / union if union else 0.0
    print('IoU %.4f over %d layers (%d pixels in the union)' % (iou, len(m['layers']), union))
    return 0 if iou >= a.min else 1


if __name__ == '__main__':
    sys.exit(main())
