-- samples/wu_mmo.lua - Wu's first worked example (Wu 3, Fig. 22-23): a multi-material object
-- of three materials: feature the y axis, d- = 21.17, dg = 0 (no gradient: a step), d+ = 8.83,
-- Ms = [0.1, 0.7, 0.2] inside radius 21.17 around the y axis and Me = [0.7, 0.1, 0.2] beyond.
-- The part is a block whose corners lie 30 = d- + d+ from the axis.
-- usage: hovox run samples/wu_mmo.lua [OUTDIR]
local out = arg[1] or "."
hovox.mkdir(out) -- the output directory and its parents, as mkdir -p

local h = 30 / math.sqrt(2)
local mesh = hovox.generate.box{min = {-h, 0, -h}, max = {h, 50, h}}
mesh:save(out .. "/wu_mmo.stl")
local model = hovox.voxelize(mesh, {dims = 128})
local mats = hovox.materials{
    {name = "M1", color = "#9467bd"}, {name = "M2", color = "#8c564b"}, {name = "M3", color = "#e377c2"},
}
local mmo = hovox.object(model, mats)
mmo:add_ags{feature = hovox.axis{origin = {0, 0, 0}, direction = {0, 1, 0}},
            d_neg = 21.17, d_grad = 0, d_pos = 8.83, ms = {0.1, 0.7, 0.2}, me = {0.7, 0.1, 0.2}}
local graded = mmo:evaluate()
graded:save(out .. "/wu_mmo.vdb")
-- Wu Fig. 23 (c): sample lines S1 (across the middle) and S2 (a diagonal through the corners)
graded:profile{from = {-h, 25, 0}, to = {h, 25, 0}, samples = 300, csv = out .. "/wu_mmo_S1.csv",
               plot = out .. "/wu_mmo_S1.png", title = "Wu MMO: material along S1"}
graded:profile{from = {-h, 25, -h}, to = {h, 25, h}, samples = 300, csv = out .. "/wu_mmo_S2.csv",
               plot = out .. "/wu_mmo_S2.png", title = "Wu MMO: material along S2 (diagonal)"}
local _, centre = graded:probe{0, 25, 0}
local _, corner = graded:probe{h - 0.5, 25, h - 0.5}
print(string.format("mmo: centre M1 %.2f M2 %.2f, corner M1 %.2f M2 %.2f", centre.M1, centre.M2,
                    corner.M1, corner.M2))
print("outputs in " .. out)
