# samples/python/wu_shaft.py - Wu's second worked example (Wu 3, Fig. 24-26) in Python, as
# samples/wu_shaft.lua does it: a 150 x 55 x 55 shaft of three materials graded from the model's
# contour inward with a sine: d- = 0, dg = 20.416, d+ = 0, f(d) = sin(0.1538 d), Ms = [0, 0, 1],
# Me = [0, 0.2, 0.8], on a (256, 97, 97) voxel grid. Notebook-style: run it whole, or cell by
# cell (# %%).
# usage: python3 samples/python/wu_shaft.py [OUTDIR]
# %%
import sys

import numpy as np

import hovox

out = sys.argv[1] if len(sys.argv) > 1 else "."

# %%
mesh = hovox.generate.cylinder(base=(0, 0, 0), axis=0, length=150, radius=27.5, segments=192)
mesh.save(out + "/wu_shaft.stl")
model = hovox.voxelize(mesh, dims=(256, 97, 97))
mats = hovox.materials([{"name": "M1", "color": "#d62728"}, {"name": "M2", "color": "#1f77b4"},
                        {"name": "M3", "color": "#bcbd22"}])
shaft = hovox.object(model, mats)
src = shaft.add_ags(feature=model.contour(), d_neg=0, d_grad=20.416, d_pos=0, f="sin(0.1538*d)", ms=(0, 0, 1),
                    me=(0, 0.2, 0.8))
graded = shaft.evaluate()
graded.save(out + "/wu_shaft.vdb")

# %% Wu Fig. 26: the material along three lines through the centre (S1, S2 radial, S3 axial)
for name, a, b in [("S1", (75, -27.5, 0), (75, 27.5, 0)), ("S2", (75, 0, -27.5), (75, 0, 27.5)),
                   ("S3", (0, 5, 5), (150, 5, 5))]:
    graded.profile(from_=a, to=b, samples=400, csv=out + "/wu_shaft_" + name + ".csv",
                   plot=out + "/wu_shaft_" + name + ".png", title="Wu shaft: material along " + name)

# %% the distribution function itself (Fig. 26 a), as the source evaluates it: eval takes an array
d = 27.5 * np.arange(101) / 100
p = src.eval(d)
with open(out + "/wu_shaft_mdf.csv", "w") as f:
    f.write("d,M1,M2,M3\n")
    for i in range(101):
        f.write("%.4f,%.6f,%.6f,%.6f\n" % (d[i], p[i, 0], p[i, 1], p[i, 2]))
_, c = graded.probe((75, 0, 0))
_, s = graded.probe((75, 0, 27.5 - 10.2))
print("shaft: %d voxels; centre M2 %.3f, 10.2 mm deep M2 %.3f (max 0.2)" % (graded.voxels("occupancy"), c["M2"], s["M2"]))
print("outputs in " + out)
