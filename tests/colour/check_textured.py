#!/usr/bin/python3
"""tests/colour/check_textured.py HOVOX DIR - one textured part read two ways gives the same colour
(issue 29 checks): tests/colour/textured_cube.py writes a cube whose faces map an 8 x 8 colour ramp
as a 3MF texture2d group and as OBJ + MTL map_Kd + PNG; both are voxelized and painted 1.5 mm deep
at 0.5 mm, and every voxel centre's six fractions (hovox probe) agree within 0.01. The ramp must
show: fractions at two corners of a face differ (the texture is sampled, not a flat colour)."""
import os
import subprocess
import sys

RESINS = ["VeroCyan-V", "VeroMagenta-V", "VeroYellow-V", "VeroBlackPlus", "VeroPureWhite", "VeroClear"]


def probe(hovox, model, points_csv):
    out = subprocess.run([hovox, "probe", model, "--points", points_csv], check=True, capture_output=True,
                         text=True).stdout.strip().split("\n")
    head = out[0].split(",")
    return [dict(zip(head, map(float, line.split(",")))) for line in out[1:]]


def main():
    hovox, d = sys.argv[1], sys.argv[2]
    here = os.path.dirname(os.path.abspath(__file__))
    subprocess.run([sys.executable, os.path.join(here, "textured_cube.py"), d], check=True)
    for name in ("cube.3mf", "cube.obj"):
        subprocess.run([hovox, "voxelize", os.path.join(d, name), "--voxel-size", "0.5", "--colour-depth", "1.5",
                        "-o", os.path.join(d, name + ".vdb"), "-q"], check=True, capture_output=True)
    pts = os.path.join(d, "points.csv")
    centres = [-0.25 + 0.5 * i for i in range(22)]
    with open(pts, "w") as f:
        f.write("x,y,z\n")
        for x in centres:
            for y in centres:
                for z in centres:
                    f.write("%g,%g,%g\n" % (x, y, z))
    a = probe(hovox, os.path.join(d, "cube.3mf.vdb"), pts)
    b = probe(hovox, os.path.join(d, "cube.obj.vdb"), pts)
    worst, inside = 0.0, 0
    for p, q in zip(a, b):
        if p["inside"] != q["inside"]:
            sys.exit("(%g, %g, %g): inside %g in the 3MF's model, %g in the OBJ's" % (p["x"], p["y"], p["z"],
                                                                                     p["inside"], q["inside"]))
        if not p["inside"]:
            continue
        inside += 1
        worst = max([worst] + [abs(p[r] - q[r]) for r in RESINS])
    corner = [p for p in a if (p["x"], p["y"], p["z"]) in ((0.75, 0.75, 0.25), (9.25, 9.25, 0.25))]
    spread = max(abs(corner[0][r] - corner[1][r]) for r in RESINS)
    if spread < 0.1:
        sys.exit("the bottom face's corners print alike (%.3f): the texture was not sampled" % spread)
    if worst > 0.01:
        sys.exit("3MF and OBJ differ by %.4f > 0.01" % worst)
    print("textured cube: %d voxels, 3MF texture2d and OBJ map_Kd fractions within 0.01 (the ramp spans %.2f)"
          % (inside, spread))


if __name__ == "__main__":
    main()
