-- samples/stress_graded_beam.lua - design by data, closed loop (issue 18): a cantilever beam is
-- voxelized, its bending stress from beam theory is written to .vti as an FEA tool would deliver
-- it, read back as a field feature, and the beam is graded so that the highly stressed fibres
-- get the stiff material: a property target (Young's modulus rising linearly with |sigma|)
-- through a calibration table of a rigid/rubber-like PolyJet pair.
-- Outputs: the stress field (.vti), the table (.csv), the graded model (.vdb), a profile of the
-- fractions and the modulus across the section (CSV + PNG), a cut render, a J750 stack.
-- usage: hovox run samples/stress_graded_beam.lua [OUTDIR] [VOXEL] [LAYERS]
--   VOXEL: voxel size in mm (default 0.5); LAYERS: the J750 layers to write, "A:B" (layers A to
--   B-1), "all" (default: 370 layers) or "none"
-- test-args: 2 180:183
local out = arg[1] or "."
hovox.mkdir(out) -- the output directory and its parents, as mkdir -p
local voxel = tonumber(arg[2] or "0.5")
local stack = arg[3] or "all"
local range
if stack ~= "all" and stack ~= "none" then
    local a, b = stack:match("^(%d+):(%d+)$")
    assert(a, "LAYERS must be A:B, all or none, not " .. stack)
    range = {tonumber(a), tonumber(b)}
end

-- 1. the beam: length L along x (clamped at x = 0), height h along y (neutral axis y = 0),
-- width b along z; a tip load P at x = L
local L, h, b, P = 100.0, 20.0, 10.0, 100.0 -- mm, mm, mm, N
local mesh = hovox.generate.box{min = {0, -h / 2, 0}, max = {L, h / 2, b}}
mesh:save(out .. "/beam.stl")
local beam = hovox.voxelize(mesh, {voxel_size = voxel})

-- 2. bending stress from beam theory: M(x) = P (L - x), I = b h^3 / 12, |sigma| = |M y / I| (MPa),
-- at every voxel centre (surface voxels' centres may lie just outside the box: beam theory is
-- evaluated at the nearest point of the beam), written to .vti through the export path
local I = b * h ^ 3 / 12
local function clamp(v, lo, hi) return math.max(lo, math.min(hi, v)) end
local function sigma(x, y) return math.abs(P * (L - clamp(x, 0, L)) * clamp(y, -h / 2, h / 2) / I) end
beam:add_grid("sigma", function(x, y, z) return sigma(x, y) end)
local vti = out .. "/beam_stress.vti"
local ex = beam:export{path = vti, grids = "sigma"}
print(string.format("stress field: %s, %d points, arrays %s (max |sigma| = P L h / 2I = %.2f MPa)", vti, ex.points,
                    ex.arrays, P * L * h / 2 / I))

-- 3. the stress read back as a field feature: its value plays the role of d
local stress, range_of = beam:field{file = vti, array = "sigma", outside = "nearest"}
print(string.format("field: %.4g to %.4g MPa over %d voxels (in the file %.4g to %.4g)", range_of.lo, range_of.hi,
                    range_of.voxels, range_of.file_lo, range_of.file_hi))

-- 4. a calibration table of a rigid/rubber-like pair along Ms = rubber -> Me = rigid (tensile
-- modulus in MPa: near the rubber for most of the path, then a jump), written next to the outputs
local table_csv = out .. "/rigid_rubber_modulus.csv"
local f = assert(io.open(table_csv, "w"))
f:write("# tensile modulus of rigid/rubber-like blends; t = fraction of the way from Ms to Me\n",
        "t,youngs_modulus[MPa]\n",
        "0,0.6\n0.1,0.9\n0.2,1.5\n0.3,2.6\n0.4,4.8\n0.5,9.5\n0.6,20\n0.7,60\n0.8,250\n0.9,900\n1,2000\n")
f:close()
-- the modulus rises linearly with the stress, from 5 MPa where the beam is unloaded to 2 GPa at
-- the highest stress on the model
local mats = hovox.materials{{name = "rigid", color = "#1f4e9c"}, {name = "rubber", color = "#f2a541"}}
local obj = hovox.object(beam, mats)
obj:add_ags{name = "stress", feature = stress, ranges = {0, range_of.hi, 0}, ms = {0, 1}, me = {1, 0},
            calibration = table_csv, property_grading = "youngs_modulus", ps = "5MPa", pe = "2GPa"}
local graded = obj:evaluate()
graded:save(out .. "/stress_graded_beam.vdb")

-- 5. outputs: fractions and modulus across the section at x = L/4, where the stress is high
local xq = L / 4
local prof = graded:profile{from = {xq, -h / 2, b / 2}, to = {xq, h / 2, b / 2}, samples = 161,
                            property = "youngs_modulus", csv = out .. "/beam_section.csv",
                            plot = out .. "/beam_section.png",
                            title = string.format("Stress-graded beam: section at x = %g mm", xq)}
-- check the loop: at the outer fibre the modulus is the target for the stress there
local e = prof.property.values
local n = #e
local top = prof.t[n] - h / 2 -- y of the last sample
local want = 5 + sigma(xq, top) / range_of.hi * (2000 - 5)
print(string.format("at (%g, %g): %s %.1f %s, the target %.1f (|sigma| %.2f MPa); at the neutral axis %.2f %s", xq, top,
                    prof.property.name, e[n], prof.property.unit, want, sigma(xq, top), e[(n + 1) // 2],
                    prof.property.unit))
assert(math.abs(e[n] - want) / want < 0.05, "the modulus at the outer fibre is off its target")
-- the mid-plane z = b/2 seen from above: rigid (blue) along the stressed top and bottom fibres near
-- the clamp, rubber-like (orange) along the neutral axis and towards the free end
graded:render{path = out .. "/beam_cut.png", surface = true, clip = string.format("z>%g", b / 2), view = "top",
              size = {1000, 300}}
if stack ~= "none" then
    local st = graded:layers{mesh = mesh, dir = out .. "/beam_j750", profile = "j750", layers = range}
    print(string.format("J750 stack: layers %d to %d of %d, %d x %d pixels; achieved rigid %.4f rubber %.4f", st.first,
                        st.last - 1, st.layers, st.width, st.height, st.materials.rigid.achieved,
                        st.materials.rubber.achieved))
end
print("outputs in " .. out)
