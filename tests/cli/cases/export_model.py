# tests/cli/cases/export_model.py - a small graded model for the export CLI tests, written with
# pyopenvdb (independent of hovox's writer): 12 x 6 x 4 voxels of 0.5 mm at index (0,0,0),
# a hole at i = 5, j = 2..3; materials a and b, b = i / 11 (a linear gradient along x).
#   export_model.py OUT.vdb [--bad]   (--bad: fractions at voxel (7, 1, 2) sum to 0.5)
import json
import sys

import numpy as np
import pyopenvdb as vdb

n = (12, 6, 4)
occ = np.ones(n, dtype=bool)
occ[5, 2:4, :] = False
fb = np.zeros(n, dtype=np.float32)
for i in range(n[0]):
    fb[i] = i / 11.0
fa = (1.0 - fb).astype(np.float32)
fa[~occ] = 0
fb[~occ] = 0
if "--bad" in sys.argv:
    fa[7, 1, 2] = fb[7, 1, 2] = 0.25
xf = vdb.createLinearTransform(voxelSize=0.5)
grids = []
g = vdb.BoolGrid()
g.copyFromArray(occ)
g.name = "occupancy"
g.transform = xf
grids.append(g)
for name, arr in (("a", fa), ("b", fb)):
    f = vdb.FloatGrid()
    f.copyFromArray(arr, tolerance=-1)
    f.name = "material." + name
    f.transform = xf
    grids.append(f)
props = lambda rho, e, nu: {"density": {"value": rho, "unit": "kg/m^3"},
                            "youngs_modulus": {"value": e, "unit": "Pa"},
                            "poisson_ratio": {"value": nu, "unit": "1"}}
table = {"materials": [{"name": "a", "color": [0, 0, 1, 1], "properties": props(1000, 1e6, 0.45)},
                       {"name": "b", "color": [1, 0, 0, 1], "properties": props(2000, 1e9, 0.3)}]}
vdb.write(sys.argv[1], grids=grids, metadata={"hovox.materials.json": json.dumps(table)})
