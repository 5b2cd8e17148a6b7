"""scripts/bench/python_bench.py - figures of the Python package (issue 31), not part of `make bench`:
  1. Model.fractions() of a 256^3 graded model (3 materials): GB/s of the dense float32 array made;
  2. a grade from Python (load, object, source, evaluate, save, in one process) against the same
     `hovox grade` command, end to end, runs interleaved so both see the same machine load.
usage: PYTHONPATH=python /usr/bin/python3 scripts/bench/python_bench.py [--runs N] [--hovox build/hovox]
Prints medians (the machine may be shared: the spread is printed too)."""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import hovox


def median_spread(xs):
    return statistics.median(xs), min(xs), max(xs)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--hovox", default=os.path.join(os.path.dirname(__file__), "..", "..", "build", "hovox"))
    ap.add_argument("--knot-dims", type=int, default=512)
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="hovox-pybench-")

    # 1. dense fractions of a 256^3 model: a box voxelized at 256 per side, graded from an axis
    box = hovox.generate.box(min=(0, 0, 0), max=(256, 256, 256))
    model = hovox.voxelize(box, voxel_size=1.0001)
    obj = hovox.object(model, hovox.materials(["A", "B", "C"]))
    obj.add_ags(feature=hovox.axis(origin=(128, 128, 0), direction=(0, 0, 1)), d_neg=10, d_grad=150, d_pos=0,
                ms=(0.8, 0.1, 0.1), me=(0.1, 0.1, 0.8))
    graded = obj.evaluate()
    lo, hi = graded.index_box()
    shape = tuple(h - l + 1 for l, h in zip(lo, hi))
    times = []
    for _ in range(a.runs):
        t = time.perf_counter()
        f = graded.fractions()
        times.append(time.perf_counter() - t)
        del f
    med, mn, mx = median_spread(times)
    nbytes = shape[0] * shape[1] * shape[2] * 3 * 4
    print("fractions(): %s x 3 float32 (%.0f MB, %d voxels occupied), threads %d: median %.4f s (%.4f-%.4f) = "
          "%.2f GB/s (best %.2f GB/s)" % ("x".join(map(str, shape)), nbytes / 1e6, graded.voxels("occupancy"),
                                          hovox.threads(), med, mn, mx, nbytes / med / 1e9, nbytes / mn / 1e9))
    graded.free()
    obj.free()
    model.free()

    # 2. grade: Python against `hovox grade`, same input and options
    knot = hovox.generate.knot(facets=200000)
    src = os.path.join(work, "knot.vdb")
    hovox.voxelize(knot, dims=a.knot_dims).save(src)
    cli = [a.hovox, "grade", src, "-o", os.path.join(work, "cli.vdb"), "--materials", "A,B,C", "--frf",
           "axis:0,0,0:0,0,1", "--ranges", "0,40,0", "--f", "d/dg", "--ms", "0,0.9,0.1", "--me", "0.9,0,0.1"]
    py_code = (
        "import hovox, sys\n"
        "m = hovox.load(sys.argv[1])\n"
        "o = hovox.object(m, hovox.materials(['A', 'B', 'C']))\n"
        "o.add_ags(feature=hovox.axis(origin=(0, 0, 0), direction=(0, 0, 1)), ranges=(0, 40, 0), f='d/dg',\n"
        "          ms=(0, 0.9, 0.1), me=(0.9, 0, 0.1))\n"
        "o.evaluate().save(sys.argv[2])\n")
    py = [sys.executable, "-c", py_code, src, os.path.join(work, "py.vdb")]
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)

    def wall(cmd):
        t = time.perf_counter()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, env=env)
        return time.perf_counter() - t

    # in process: the calls alone (no interpreter start, no import)
    def in_process():
        t = time.perf_counter()
        m = hovox.load(src)
        o = hovox.object(m, hovox.materials(["A", "B", "C"]))
        o.add_ags(feature=hovox.axis(origin=(0, 0, 0), direction=(0, 0, 1)), ranges=(0, 40, 0), f="d/dg",
                  ms=(0, 0.9, 0.1), me=(0.9, 0, 0.1))
        o.evaluate().save(os.path.join(work, "inproc.vdb"))
        return time.perf_counter() - t

    wall(cli), wall(py), in_process()  # warm the page cache
    tc, tp, ti = [], [], []
    for _ in range(a.runs):
        tc.append(wall(cli))
        tp.append(wall(py))
        ti.append(in_process())
    c, p, i = median_spread(tc), median_spread(tp), median_spread(ti)
    print("grade (knot at %d, axis source, load + grade + save): hovox grade %.4f s (%.4f-%.4f); python3 process "
          "%.4f s (%.4f-%.4f) = %.3fx; the calls in process %.4f s (%.4f-%.4f) = %.3fx" % (
              a.knot_dims, c[0], c[1], c[2], p[0], p[1], p[2], p[0] / c[0], i[0], i[1], i[2], i[0] / c[0]))
    same = [open(os.path.join(work, f), "rb").read() for f in ("cli.vdb", "py.vdb")]
    print("same model as the CLI's (bytes after the header's UUID): %s" % (same[0][57:] == same[1][57:]))


if __name__ == "__main__":
    main()
