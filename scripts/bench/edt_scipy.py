#!/usr/bin/python3
"""scripts/bench/edt_scipy.py - the anchor of the EDT benchmark (run with /usr/bin/python3,
which has numpy and scipy).

  edt_scipy.py make sphere N OUT.raw     solid ball of radius 0.45 N centred in an N^3 grid,
                                         uint8 (1 inside), z fastest
  edt_scipy.py time MASK.raw N|NX,NY,NZ [--runs R] [--compare OURS.f32]
      times scipy.ndimage.distance_transform_edt(mask) alone (median of R runs), prints
      "scipy median S s min S max S runs R peak MiB M"; with --compare also prints the
      largest absolute difference from our float32 distances ("max_abs_diff D").
"""
import os
import resource
import sys
import time

import numpy as np
from scipy import ndimage


def make_sphere(n, out):
    c = (n - 1) / 2.0
    r2 = (0.45 * n) ** 2
    x = np.arange(n, dtype=np.float64) - c
    yz = x[:, None] ** 2 + x[None, :] ** 2
    with open(out + ".tmp", "wb") as f:
        for i in range(n):  # slice by slice: no N^3 float temporaries
            f.write((yz + x[i] ** 2 <= r2).astype(np.uint8).tobytes())
    os.replace(out + ".tmp", out)


def time_scipy(path, n, runs, compare):
    dims = tuple(int(x) for x in n.split(",")) if "," in n else (int(n),) * 3
    count = dims[0] * dims[1] * dims[2]
    mask = np.fromfile(path, dtype=np.uint8)
    if mask.size != count:
        sys.exit("edt_scipy.py: %s holds %d bytes, expected %d" % (path, mask.size, count))
    mask = mask.reshape(dims)
    times = []
    dist = None
    for _ in range(runs):
        dist = None  # free the previous result before the next run
        t0 = time.perf_counter()
        dist = ndimage.distance_transform_edt(mask)
        times.append(time.perf_counter() - t0)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print("scipy median %.4f s min %.4f max %.4f runs %d peak %.1f MiB"
          % (float(np.median(times)), min(times), max(times), runs, peak))
    if compare:
        ours = np.fromfile(compare, dtype=np.float32)
        if ours.size != count:
            sys.exit("edt_scipy.py: %s holds %d floats, expected %d" % (compare, ours.size, count))
        diff = np.abs(ours.reshape(dims).astype(np.float64) - dist)
        print("max_abs_diff %.3g max_distance %.6g" % (float(diff.max()), float(dist.max())))


def main(argv):
    if len(argv) >= 4 and argv[1] == "make" and argv[2] == "sphere":
        make_sphere(int(argv[3]), argv[4])
    elif len(argv) >= 4 and argv[1] == "time":
        runs, compare = 1, None
        rest = argv[4:]
        while rest:
            if rest[0] == "--runs" and len(rest) > 1:
                runs = int(rest[1])
                rest = rest[2:]
            elif rest[0] == "--compare" and len(rest) > 1:
                compare = rest[1]
                rest = rest[2:]
            else:
                sys.exit("edt_scipy.py: unknown argument %s" % rest[0])
        time_scipy(argv[2], argv[3], max(1, runs), compare)
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv)
