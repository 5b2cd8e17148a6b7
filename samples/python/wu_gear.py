# samples/python/wu_gear.py - Wu's third worked example (Wu 3, Fig. 27) in Python, as
# samples/wu_gear.lua does it: a gear of three materials graded from two fixed reference features,
# the z axis and the bottom plane; AGS union of the two sources, then the heterogeneous union of two
# objects, sliced for a Stratasys J750. Notebook-style: run it whole, or cell by cell (# %%).
# usage: python3 samples/python/wu_gear.py [OUTDIR] [DIMS] [LAYERS]
#   DIMS: voxels along the longest side (default 128); LAYERS: "A:B", "all" (default) or "none"
# test-args: 96 700:704
# %%
import sys

import numpy as np

import hovox

out = sys.argv[1] if len(sys.argv) > 1 else "."
dims = int(sys.argv[2]) if len(sys.argv) > 2 else 128
stack = sys.argv[3] if len(sys.argv) > 3 else "all"
layers = None
if stack not in ("all", "none"):
    a, b = stack.split(":")
    layers = (int(a), int(b))

# %% the gear: 24 teeth, tip radius 39.45 (= d- + dg + d+ of the axis source), a bore of 9.54 (= d-
# of the axis source), height 39.45 (= the sum of the bottom-plane source's ranges)
mesh = hovox.generate.gear(teeth=24, root=34.5, tip=39.45, bore=9.54, height=39.45)
mesh.save(out + "/wu_gear.stl")
model = hovox.voxelize(mesh, dims=dims)

mats = hovox.materials([
    {"name": "A", "color": "#1f77b4", "density": 1180, "youngs_modulus": 2.0e9, "poisson_ratio": 0.38},
    {"name": "B", "color": "#ff7f0e", "density": 1120, "youngs_modulus": 0.6e6, "poisson_ratio": 0.48},
    {"name": "C", "color": "#2ca02c", "density": 1300, "youngs_modulus": 2.5e9, "poisson_ratio": 0.35},
])
ms, me = (0, 0.9, 0.1), (0.9, 0, 0.1)
z_axis = hovox.axis(origin=(0, 0, 0), direction=(0, 0, 1))
bottom = hovox.plane(point=(0, 0, 0), normal=(0, 0, 1))

# %% Wu's f(d) = 0.105 d over dg = 9.54 reaches 1.0017: it leaves [0, 1], and hovox says so
try:
    hovox.ags(feature=z_axis, d_neg=9.54, d_grad=9.54, d_pos=20.37, f="0.105*d", ms=ms, me=me)
    raise SystemExit("Wu's f(d) = 0.105 d must be refused")
except hovox.InvalidError as e:
    print("Wu's f(d) = 0.105*d:", e)
try:
    hovox.ags(feature=bottom, d_neg=3.18, d_grad=22.26, d_pos=14.01, f="0.105*d", ms=ms, me=me)
    raise SystemExit("0.105 d over the plane's range must be refused")
except hovox.InvalidError as e:
    print("the same f on the plane's range:", e)
# ... so both sources use the normalised form f(d) = d / dg
radial = hovox.ags(name="z axis", feature=z_axis, d_neg=9.54, d_grad=9.54, d_pos=20.37, f="d/dg", ms=ms, me=me)
axial = hovox.ags(name="bottom plane", feature=bottom, d_neg=3.18, d_grad=22.26, d_pos=14.01, f="d/dg", ms=ms, me=me)

# %% Fig. 27 (c, d): the axis source alone; (e, f): the plane source alone; (g, h): AGS union;
# (m, n): the heterogeneous union of (f) and (h)
h_axis = hovox.object(model, mats)
h_axis.add_ags(radial)
h_plane = hovox.object(model, mats)
h_plane.add_ags(axial)
h_both = hovox.object(model, mats)
h_both.add_ags(radial)
h_both.add_ags(axial)
h_union = h_plane | h_both  # h_plane.union(h_both)

# %% each stage: the model, profiles, a cut-away render; the stack of the final object
for name, h in [("axis", h_axis), ("plane", h_plane), ("ags_union", h_both), ("ho_union", h_union)]:
    graded = h.evaluate()
    graded.save(out + "/wu_gear_" + name + ".vdb")
    graded.profile(from_=(0, -39.4, 19.7), to=(0, 39.4, 19.7), samples=400,
                   csv=out + "/wu_gear_" + name + "_radial.csv", plot=out + "/wu_gear_" + name + "_radial.png",
                   title="Wu gear (" + name + "): radial line at z = 19.7 mm")
    graded.profile(from_=(25, 0, 0), to=(25, 0, 39.45), samples=300,
                   csv=out + "/wu_gear_" + name + "_axial.csv", plot=out + "/wu_gear_" + name + "_axial.png",
                   title="Wu gear (" + name + "): axial line at r = 25 mm")
    graded.render(out + "/wu_gear_" + name + "_cut.png", surface=True, clip="x>0&y<0", size=(640, 640))
    if name == "ho_union" and stack != "none":
        st = graded.layers(mesh, out + "/wu_gear_j750", profile="j750", layers=layers)
        m = st["materials"]
        print("J750 stack: layers %d to %d of %d, %d x %d pixels; achieved A %.4f B %.4f C %.4f" % (
            st["first"], st["last"] - 1, st["layers"], st["width"], st["height"], m["A"]["achieved"],
            m["B"]["achieved"], m["C"]["achieved"]))
    inside, f = graded.probe((0, 15, 20))
    print("%-10s %d voxels; at (0, 15, 20): A %.3f B %.3f C %.3f" % (name, graded.voxels("occupancy"), f["A"], f["B"],
                                                                   f["C"]))
    # the whole model as an array: mean composition over the occupied voxels
    frac, occ = graded.fractions(), graded.occupancy()
    print("%-10s mean A %.3f B %.3f C %.3f" % ((name,) + tuple(np.round(frac[occ].mean(axis=0), 3))))
    graded.free()
print("outputs in " + out)
