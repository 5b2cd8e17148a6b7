-- samples/colour_cube.lua - full colour (issue 29): a 10 mm cube whose six faces carry six flat
-- colours (samples/colour_cube.obj and its MTL: red, green, blue, yellow, cyan, magenta) is
-- voxelized and painted 1 mm deep in its colours over a soft Agilus30 core: each colour goes
-- through LittleCMS and the default CMYK profile (Ghostscript's default_cmyk.icc) into the J750's
-- six colour resins (VeroCyan-V, VeroMagenta-V, VeroYellow-V, VeroBlackPlus, VeroPureWhite,
-- VeroClear; the printer has six slots, so Agilus30 takes VeroClear's, which no colour here
-- uses). Outputs: the model (.vdb), the fractions at each face and the centre (.csv), a render in the requested colours and a cut through the core (.png), the model as a 3MF Volumetric
-- package with its colours (.3mf), a J750 blue-noise stack whose manifest gives the skin's mean dE2000.
-- usage: hovox run samples/colour_cube.lua [OUTDIR] [VOXEL] [LAYERS]
--   VOXEL: voxel size in mm (default 0.25); LAYERS: the J750 layers to write, "A:B" (layers A to
--   B-1), "all" (default: 370 layers) or "none"
-- test-args: 0.5 18:20
local out = arg[1] or "."
hovox.mkdir(out)
local voxel = tonumber(arg[2] or "0.25")
local stack = arg[3] or "all"
local range
if stack ~= "all" and stack ~= "none" then
    local a, b = stack:match("^(%d+):(%d+)$")
    assert(a, "LAYERS must be A:B, all or none, not " .. stack)
    range = {tonumber(a), tonumber(b)}
end

local mesh = hovox.load_mesh("samples/colour_cube.obj")
local model = hovox.voxelize(mesh, {voxel_size = voxel})
model:paint(mesh, {colour_depth = 1, core = "Agilus30"})
model:save(out .. "/colour_cube.vdb")

-- the fractions half a millimetre inside each face, and at the centre
local resins = {"VeroCyan-V", "VeroMagenta-V", "VeroYellow-V", "VeroBlackPlus", "VeroPureWhite", "VeroClear", "Agilus30"}
local points = {
    {"red (-z)", {5, 5, 0.5}}, {"green (+z)", {5, 5, 9.5}}, {"blue (-y)", {5, 0.5, 5}},
    {"yellow (+x)", {9.5, 5, 5}}, {"cyan (+y)", {5, 9.5, 5}}, {"magenta (-x)", {0.5, 5, 5}}, {"centre", {5, 5, 5}},
}
local csv = assert(io.open(out .. "/colour_cube_fractions.csv", "w"))
csv:write("where,x,y,z," .. table.concat(resins, ",") .. "\n")
for _, p in ipairs(points) do
    local _, f = model:probe(p[2])
    local row = {}
    for i, r in ipairs(resins) do row[i] = string.format("%.4f", f[r] or 0) end
    csv:write(string.format("%s,%g,%g,%g,%s\n", p[1], p[2][1], p[2][2], p[2][3], table.concat(row, ",")))
    print(string.format("%-13s %s", p[1], table.concat(row, " ")))
end
csv:close()

-- the part in the colours asked for, and cut open to show the core
model:render{path = out .. "/colour_cube.png", surface = true, size = {480, 480}}
model:render{path = out .. "/colour_cube_cut.png", surface = true, clip = "x>5&y<5", size = {480, 480}}

-- the model as a 3MF Volumetric package: the resins as its composite, the colours asked for as its
-- <v:color> (16-bit RGBA, linear sRGB); read back, the same fractions within 1/255
local pkg = model:export{path = out .. "/colour_cube.3mf", volumetric = true}
local back = hovox.load(out .. "/colour_cube.3mf")
local worst = 0
for _, p in ipairs(points) do
    local _, fa = model:probe(p[2])
    local _, fb = back:probe(p[2])
    for _, r in ipairs(resins) do worst = math.max(worst, math.abs((fa[r] or 0) - (fb[r] or 0))) end
end
assert(worst <= 1 / 255 + 1e-6, "fractions read back from the package differ by " .. worst)
print(string.format("3MF Volumetric: stacks %s; read back, fractions within %.4f", pkg.arrays, worst))

if stack ~= "none" then
    local st = model:layers{mesh = mesh, dir = out .. "/colour_cube_j750", profile = "j750", layers = range}
    print(string.format("J750 stack: layers %d to %d of %d; skin mean dE2000 %.2f achieved, %.2f target over %d voxels",
                        st.first, st.last - 1, st.layers, st.colour.mean_de2000_achieved, st.colour.mean_de2000_target,
                        st.colour.skin_voxels))
end
print("outputs in " .. out)
