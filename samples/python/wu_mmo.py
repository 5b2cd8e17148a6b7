# samples/python/wu_mmo.py - Wu's first worked example (Wu 3, Fig. 22-23) in Python, as
# samples/wu_mmo.lua does it: a multi-material object of three materials, feature the y axis,
# d- = 21.17, dg = 0 (a step), d+ = 8.83, Ms = [0.1, 0.7, 0.2] inside radius 21.17, Me = [0.7, 0.1,
# 0.2] beyond. Notebook-style: run it whole, or cell by cell (# %%).
# usage: python3 samples/python/wu_mmo.py [OUTDIR]
# %%
import math
import sys

import numpy as np

import hovox

out = sys.argv[1] if len(sys.argv) > 1 else "."

# %% a block whose corners lie 30 = d- + d+ from the axis
h = 30 / math.sqrt(2)
mesh = hovox.generate.box(min=(-h, 0, -h), max=(h, 50, h))
mesh.save(out + "/wu_mmo.stl")
model = hovox.voxelize(mesh, dims=128)
mats = hovox.materials([{"name": "M1", "color": "#9467bd"}, {"name": "M2", "color": "#8c564b"},
                        {"name": "M3", "color": "#e377c2"}])
mmo = hovox.object(model, mats)
mmo.add_ags(feature=hovox.axis(origin=(0, 0, 0), direction=(0, 1, 0)), d_neg=21.17, d_grad=0, d_pos=8.83,
            ms=(0.1, 0.7, 0.2), me=(0.7, 0.1, 0.2))
graded = mmo.evaluate()
graded.save(out + "/wu_mmo.vdb")

# %% Wu Fig. 23 (c): sample lines S1 (across the middle) and S2 (a diagonal through the corners)
graded.profile(from_=(-h, 25, 0), to=(h, 25, 0), samples=300, csv=out + "/wu_mmo_S1.csv",
               plot=out + "/wu_mmo_S1.png", title="Wu MMO: material along S1")
graded.profile(from_=(-h, 25, -h), to=(h, 25, h), samples=300, csv=out + "/wu_mmo_S2.csv",
               plot=out + "/wu_mmo_S2.png", title="Wu MMO: material along S2 (diagonal)")
_, centre = graded.probe((0, 25, 0))
_, corner = graded.probe((h - 0.5, 25, h - 0.5))
print("mmo: centre M1 %.2f M2 %.2f, corner M1 %.2f M2 %.2f" % (centre["M1"], centre["M2"], corner["M1"], corner["M2"]))

# %% the step as arrays: the share of the voxels in Ms and in Me
frac, occ = graded.fractions(), graded.occupancy()
inner = np.isclose(frac[..., 0], 0.1) & occ
print("mmo: %d of %d voxels inside radius 21.17 (Ms)" % (inner.sum(), occ.sum()))
print("outputs in " + out)
