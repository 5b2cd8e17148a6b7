-- samples/wu_gear.lua - Wu's third worked example (Wu 3, Fig. 27): a gear of three materials
-- graded from two fixed reference features, the z axis and the bottom plane; AGS union of
-- the two sources, then the heterogeneous union of two objects.
-- The heterogeneous union is also sliced for a Stratasys J750 (Wu 2.4.2): a stack of
-- halftoned palette PNGs, one material per printer voxel.
-- usage: hovox run samples/wu_gear.lua [OUTDIR] [DIMS] [LAYERS]
--   DIMS: voxels along the longest side (default 128); LAYERS: the printer layers to write,
--   "A:B" (layers A to B-1), "all" (default: 1461 layers, about 20 s) or "none"
-- test-args: 96 700:704
local out = arg[1] or "."
hovox.mkdir(out) -- the output directory and its parents, as mkdir -p
local dims = tonumber(arg[2] or "128")
local stack = arg[3] or "all"
local range
if stack ~= "all" and stack ~= "none" then
    local a, b = stack:match("^(%d+):(%d+)$")
    assert(a, "LAYERS must be A:B, all or none, not " .. stack)
    range = {tonumber(a), tonumber(b)}
end

-- the gear: 24 teeth, tip radius 39.45 (= d- + dg + d+ of the axis source), a bore of 9.54
-- (= d- of the axis source: the gradient starts at the bore), height 39.45 (= the sum of the
-- bottom-plane source's ranges)
local mesh = hovox.generate.gear{teeth = 24, root = 34.5, tip = 39.45, bore = 9.54, height = 39.45}
mesh:save(out .. "/wu_gear.stl")
local model = hovox.voxelize(mesh, {dims = dims})

local mats = hovox.materials{
    {name = "A", color = "#1f77b4", density = 1180, youngs_modulus = 2.0e9, poisson_ratio = 0.38},
    {name = "B", color = "#ff7f0e", density = 1120, youngs_modulus = 0.6e6, poisson_ratio = 0.48},
    {name = "C", color = "#2ca02c", density = 1300, youngs_modulus = 2.5e9, poisson_ratio = 0.35},
}
local ms, me = {0, 0.9, 0.1}, {0.9, 0, 0.1}
local z_axis = hovox.axis{origin = {0, 0, 0}, direction = {0, 0, 1}}
local bottom = hovox.plane{point = {0, 0, 0}, normal = {0, 0, 1}}

-- Wu's distribution function f(d) = 0.105 d over dg = 9.54 reaches 0.105 * 9.54 = 1.0017 at the
-- end of the gradient range, so it leaves [0, 1]: hovox reports that instead of clamping.
local ok, err = pcall(hovox.ags, {feature = z_axis, d_neg = 9.54, d_grad = 9.54, d_pos = 20.37,
                                  f = "0.105*d", ms = ms, me = me})
assert(not ok, "Wu's f(d) = 0.105 d must be refused")
print("Wu's f(d) = 0.105*d: " .. err:gsub("^[^:]*:%d+: ", ""))
-- Wu gives the plane source "the same f": over its dg = 22.26 that reaches 2.34, refused too.
local ok2, err2 = pcall(hovox.ags, {feature = bottom, d_neg = 3.18, d_grad = 22.26, d_pos = 14.01,
                                    f = "0.105*d", ms = ms, me = me})
assert(not ok2, "0.105 d over the plane's range must be refused")
print("the same f on the plane's range: " .. err2:gsub("^[^:]*:%d+: ", ""))
-- ... so both sources use the normalised form, f(d) = d / dg (0.1048 d for the axis, 0.0449 d
-- for the plane), which reaches exactly 1 at the end of each range.
local radial = hovox.ags{name = "z axis", feature = z_axis, d_neg = 9.54, d_grad = 9.54,
                         d_pos = 20.37, f = "d/dg", ms = ms, me = me}
local axial = hovox.ags{name = "bottom plane", feature = bottom, d_neg = 3.18, d_grad = 22.26,
                        d_pos = 14.01, f = "d/dg", ms = ms, me = me}

-- Fig. 27 (c, d): the z axis source alone; (e, f): the bottom plane source alone
local h_axis = hovox.object(model, mats)
h_axis:add_ags(radial)
local h_plane = hovox.object(model, mats)
h_plane:add_ags(axial)
-- Fig. 27 (g, h): AGS union of both sources in one object (nearest source wins)
local h_both = hovox.object(model, mats)
h_both:add_ags(radial)
h_both:add_ags(axial)
-- Fig. 27 (m, n): the heterogeneous union of (f) and (h). On the same geometry it is one
-- region (O n O) with G1 u G2 = {plane, axis}: it equals the AGS union.
local h_union = h_plane:union(h_both)

local results = {
    {"axis", h_axis}, {"plane", h_plane}, {"ags_union", h_both}, {"ho_union", h_union},
}
for _, r in ipairs(results) do
    local name, h = r[1], r[2]
    local graded = h:evaluate()
    graded:save(out .. "/wu_gear_" .. name .. ".vdb")
    -- Wu Fig. 28: radial profile at mid-height and an axial one at r = 25
    graded:profile{from = {0, -39.4, 19.7}, to = {0, 39.4, 19.7}, samples = 400,
                   csv = out .. "/wu_gear_" .. name .. "_radial.csv",
                   plot = out .. "/wu_gear_" .. name .. "_radial.png",
                   title = "Wu gear (" .. name .. "): radial line at z = 19.7 mm"}
    graded:profile{from = {25, 0, 0}, to = {25, 0, 39.45}, samples = 300,
                   csv = out .. "/wu_gear_" .. name .. "_axial.csv",
                   plot = out .. "/wu_gear_" .. name .. "_axial.png",
                   title = "Wu gear (" .. name .. "): axial line at r = 25 mm"}
    -- Wu Fig. 27: a cut-away preview (a quarter removed) shows the gradient inside
    graded:render{path = out .. "/wu_gear_" .. name .. "_cut.png", surface = true,
                  clip = "x>0&y<0", size = {640, 640}}
    -- Wu 2.4.2: the printer's slice stack of the final object
    if name == "ho_union" and stack ~= "none" then
        local st = graded:layers{mesh = mesh, dir = out .. "/wu_gear_j750", profile = "j750", layers = range}
        print(string.format("J750 stack: layers %d to %d of %d, %d x %d pixels; achieved A %.4f B %.4f C %.4f",
                            st.first, st.last - 1, st.layers, st.width, st.height, st.materials.A.achieved,
                            st.materials.B.achieved, st.materials.C.achieved))
    end
    local inside, f = graded:probe{0, 15, 20}
    print(string.format("%-10s %d voxels; at (0, 15, 20): A %.3f B %.3f C %.3f", name,
                        graded:voxels("occupancy"), f.A, f.B, f.C))
    graded:free()
end
print("outputs in " .. out)
