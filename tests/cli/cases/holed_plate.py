# tests/cli/cases/holed_plate.py - issue 28's test part for the CLI cases, made with hovox itself in
# the current directory: a plate X x Y x Z graded A (plate.stl, plate.vdb, a.vdb), a rod of radius R
# through its middle, 1 mm longer at each end, graded B (rod.stl, rod.vdb, b.vdb), and their Boolean.
#   holed_plate.py X,Y,Z R SEGMENTS VOXEL OP OUT.vdb      ($HOVOX: the binary)
import os
import subprocess
import sys

(x, y, z), r, seg, voxel, op, out = (float(v) for v in sys.argv[1].split(",")), sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5], sys.argv[6]
hovox = os.environ["HOVOX"]
g = "%g"
steps = [
    ["generate", "box", "min=0,0,0", "max=%s" % sys.argv[1], "-o", "plate.stl"],
    ["generate", "cylinder", "base=%g,%g,-1" % (x / 2, y / 2), "axis=2", "length=" + g % (z + 2), "radius=" + r,
     "segments=" + seg, "-o", "rod.stl"],
    ["voxelize", "plate.stl", "--voxel-size", voxel, "-o", "plate.vdb", "-q"],
    ["voxelize", "rod.stl", "--voxel-size", voxel, "-o", "rod.vdb", "-q"],
    ["grade", "plate.vdb", "-o", "a.vdb", "--materials", "A,B", "--frf", "point:0,0,0", "--ranges", "0,0,0",
     "--ms", "1,0", "--me", "1,0"],
    ["grade", "rod.vdb", "-o", "b.vdb", "--materials", "A,B", "--frf", "point:0,0,0", "--ranges", "0,0,0",
     "--ms", "0,1", "--me", "0,1"],
    ["boolean", "a.vdb", op, "b.vdb", "-o", out, "-q"],
]
for s in steps:
    if subprocess.run([hovox] + s, stdout=subprocess.DEVNULL).returncode != 0:
        sys.exit("holed_plate.py: hovox %s failed" % " ".join(s))
