-- samples/wu_shaft.lua - Wu's second worked example (Wu 3, Fig. 24-26): a 150 x 55 x 55 shaft
-- of three materials graded from the model's contour (its boundary) inward with a sine:
-- d- = 0, dg = 20.416, d+ = 0, f(d) = sin(0.1538 d), Ms = [0, 0, 1], Me = [0, 0.2, 0.8], on a
-- (256, 97, 97) voxel grid.
-- usage: hovox run samples/wu_shaft.lua [OUTDIR]
local out = arg[1] or "."
hovox.mkdir(out) -- the output directory and its parents, as mkdir -p

local mesh = hovox.generate.cylinder{base = {0, 0, 0}, axis = 0, length = 150, radius = 27.5,
                                     segments = 192}
mesh:save(out .. "/wu_shaft.stl")
local model = hovox.voxelize(mesh, {dims = {256, 97, 97}})

local mats = hovox.materials{
    {name = "M1", color = "#d62728"}, {name = "M2", color = "#1f77b4"}, {name = "M3", color = "#bcbd22"},
}
local shaft = hovox.object(model, mats)
local src = shaft:add_ags{feature = model:contour(), d_neg = 0, d_grad = 20.416, d_pos = 0,
                          f = "sin(0.1538*d)", ms = {0, 0, 1}, me = {0, 0.2, 0.8}}
local graded = shaft:evaluate()
graded:save(out .. "/wu_shaft.vdb")

-- Wu Fig. 26: the distribution function, and the material along three lines through the centre
-- (S1, S2 radial, S3 along the axis)
local lines = {
    {"S1", {75, -27.5, 0}, {75, 27.5, 0}},
    {"S2", {75, 0, -27.5}, {75, 0, 27.5}},
    {"S3", {0, 5, 5}, {150, 5, 5}},
}
for _, l in ipairs(lines) do
    graded:profile{from = l[2], to = l[3], samples = 400, csv = out .. "/wu_shaft_" .. l[1] .. ".csv",
                   plot = out .. "/wu_shaft_" .. l[1] .. ".png",
                   title = "Wu shaft: material along " .. l[1]}
end
-- the distribution function itself (Fig. 26 a), as the source evaluates it
local f = io.open(out .. "/wu_shaft_mdf.csv", "w")
f:write("d,M1,M2,M3\n")
for i = 0, 100 do
    local d = 27.5 * i / 100
    local p = src:eval(d)
    f:write(string.format("%.4f,%.6f,%.6f,%.6f\n", d, p[1], p[2], p[3]))
end
f:close()
local _, c = graded:probe{75, 0, 0}
local _, s = graded:probe{75, 0, 27.5 - 10.2}
print(string.format("shaft: %d voxels; centre M2 %.3f, 10.2 mm deep M2 %.3f (max 0.2)",
                    graded:voxels("occupancy"), c.M2, s.M2))
print("outputs in " .. out)
