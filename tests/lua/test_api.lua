-- tests/lua/test_api.lua - every function of the hovox Lua module, checked against values
-- computed here. Run: hovox run tests/lua/test_api.lua TMPDIR SHARED
local tmp, shared = arg[1], arg[2]
assert(tmp and shared, "usage: test_api.lua TMPDIR SHARED")
local function near(a, b, tol, what)
    assert(math.abs(a - b) <= (tol or 1e-9), string.format("%s: %.9g vs %.9g", what or "value", a, b))
end
local function fails(pattern, fn, ...)
    local ok, err = pcall(fn, ...)
    assert(not ok, "expected an error matching " .. pattern)
    assert(tostring(err):find(pattern, 1, true), "error '" .. tostring(err) .. "' lacks '" .. pattern .. "'")
end

-- module
assert(type(hovox.version) == "string")
assert(require("hovox") == hovox)
hovox.set_threads(2)
hovox.set_threads(0)

-- meshes: load, report, count, save
local bunny = hovox.load_mesh(shared .. "/meshes/bunny_1500.stl")
local r = bunny:report()
assert(r.facets == 1500 and r.closed and r.shells == 1 and r.format == "ascii")
assert(#r.bbox.min == 3)
local nf, nv = bunny:count()
assert(nf == 1500 and nv == r.vertices)
bunny:save(tmp .. "/bunny.stl")
bunny:save(tmp .. "/bunny_ascii.stl", {ascii = true})
assert(hovox.load_mesh(tmp .. "/bunny.stl"):report().format == "binary")
assert(tostring(bunny):find("1500 facets"))
fails("No such file", hovox.load_mesh, tmp .. "/missing.stl")

-- bodies and materials (3MF build items, OBJ groups)
local boxes = hovox.load_mesh("tests/data/good/two_boxes.3mf")
assert(boxes:report().format == "3mf")
local bodies = boxes:bodies()
assert(#bodies == 2)
assert(bodies[1].name == "outer" and bodies[1].material == "VeroWhite" and bodies[1].facets == 12 and bodies[1].first == 1)
assert(bodies[2].name == "inner" and bodies[2].material == "Agilus30" and bodies[2].first == 13)
local mats3mf = boxes:materials()
assert(#mats3mf == 2 and mats3mf[2].name == "Agilus30" and #mats3mf[1].color == 4)
near(mats3mf[1].color[1], 240 / 255, 1e-9, "VeroWhite red")
assert(mats3mf[1].color[4] == 1)
local one = bunny:bodies()
assert(#one == 1 and one[1].name == "bunny_1500" and one[1].material == nil and one[1].facets == 1500)
assert(#bunny:materials() == 0)
local groups = hovox.load_mesh("tests/data/good/groups.obj")
assert(groups:bodies()[2].name == "core" and groups:materials()[1].color == nil)
assert(hovox.load_mesh("tests/data/good/tet_binary_be.ply"):report().format == "ply_binary_be")
fails("header declares 1000000000000 vertices", hovox.load_mesh, "tests/data/bad/ply_count_lies.ply")
fails("unsupported mesh format 'step'", hovox.load_mesh, "tests/data/good/part.step")

-- generators
local s = hovox.generate.sphere{radius = 5, segments = 32, rings = 16}
near(s:report().volume, 4 / 3 * math.pi * 125, 10, "sphere volume (32 x 16 polygon)")
assert(hovox.generate.box{min = {0, 0, 0}, max = {1, 2, 3}}:report().volume == 6)
assert(hovox.generate.box{min = {0, 0, 0}, max = {40, 30, 20}, hole = 8}:report().closed)
assert(hovox.generate.torus{R = 10, r = 2}:report().closed)
assert(hovox.generate.cylinder{length = 10, radius = 2}:report().closed)
assert(hovox.generate.gear{}:report().closed)
assert(hovox.generate.knot{facets = 20000}:report().facets >= 19000)
fails("radius", hovox.generate.sphere, {radius = -1})
fails("segments must be an integer", hovox.generate.sphere, {segments = 2.5})

-- voxelize, models
local box = hovox.generate.box{min = {0, 0, 0}, max = {20, 10, 10}}
local m = hovox.voxelize(box, {dims = 40, adjacency = 6, fill = "flood"})
local g = m:grids()
assert(g[1].name == "occupancy" and g[1].type == "bool" and g[2].name == "surface")
local xf = m:transform()
near(xf.voxel[1], 0.5, 1e-12, "voxel size")
assert(m:voxels() == m:voxels("occupancy"))
assert(m:voxels("surface") < m:voxels())
assert(m:meta("hovox.voxelize.json"):find('"adjacency": 6'))
assert(m:meta("nothing") == nil)
m:save(tmp .. "/box.vdb")
local m2 = hovox.load(tmp .. "/box.vdb")
assert(m2:voxels() == m:voxels())
local aniso = hovox.voxelize(box, {dims = {40, 10, 10}})
near(aniso:transform().voxel[2], 1.0, 1e-12, "anisotropic voxel")
local snapped = hovox.voxelize(box, {voxel_size = 0.5})
local like = hovox.voxelize(hovox.generate.box{min = {3, 3, 3}, max = {7, 7, 7}}, {like = snapped})
near(like:transform().origin[1], snapped:transform().origin[1], 1e-12, "same lattice")
fails("adjacency must be 6 or 26", hovox.voxelize, box, {adjacency = 18})
fails("fill must be", hovox.voxelize, box, {fill = "magic"})
fails("dims must be", hovox.voxelize, box, {dims = "x"})
fails("needs about", hovox.voxelize, box, {dims = 4000, max_memory = 1e6})

-- materials
local mats = hovox.materials{
    {name = "A", color = "#ff0000", density = 1000, youngs_modulus = 1e9},
    "B",
    {name = "C", color = {0, 0, 1}},
}
assert(mats:count() == 3)
assert(table.concat(mats:names(), ",") == "A,B,C")
assert(mats:color("A")[1] == 1 and mats:color("C")[3] == 1)
local v, unit = mats:property("A", "density")
assert(v == 1000 and unit == "kg/m^3")
assert(mats:property("B", "density") == nil)
fails("defined twice", hovox.materials, {"A", "A"})
fails("colour", hovox.materials, {{name = "X", color = "#12"}})
-- a property with its unit; a misspelt colour or a property that is not a number is refused
local pm = hovox.materials{{name = "P", density = {1.18, "g/cm^3"}}}
local pv, pu = pm:property("P", "density")
assert(pv == 1.18 and pu == "g/cm^3", pu)
fails("colour is 'color'", hovox.materials, {{name = "X", colour = "#ff0000"}})
fails("density must be a number or {value", hovox.materials, {{name = "X", density = "1180"}})
-- a misspelt option is an error, never a silent default
fails("unknown option 'dgrad'", hovox.ags, {feature = hovox.point{0, 0, 0}, dgrad = 5, ms = {1, 0}, me = {0, 1}})
fails("unknown option 'dim'", hovox.voxelize, box, {dim = 10})

-- features
local axis = hovox.axis{origin = {0, 5, 5}, direction = {1, 0, 0}}
near(axis:distance{3, 5, 8}, 3, 1e-12, "axis distance")
near(hovox.line{direction = {0, 0, 2}}:distance{3, 4, 9}, 5, 1e-12, "line distance")
near(hovox.plane{point = {0, 0, 1}, normal = {0, 0, 5}}:distance{7, 7, 4}, 3, 1e-12, "plane")
near(hovox.plane{point = {0, 0, 1}, normal = {0, 0, 5}}:distance{7, 7, -2}, 3, 1e-12, "plane behind")
near(hovox.halfspace{point = {0, 0, 1}, normal = {0, 0, 5}}:distance{7, 7, 4}, 3, 1e-12, "halfspace")
near(hovox.halfspace{point = {0, 0, 1}, normal = {0, 0, 5}}:distance{7, 7, -2}, -3, 1e-12, "halfspace behind")
do -- a signed feature takes d- < 0, a distance feature does not
    local hs = hovox.ags{feature = hovox.halfspace{normal = {1, 0, 0}}, ranges = {-5, 10, 0}, ms = {1, 0}, me = {0, 1}}
    near(hs:eval(-2.5)[2], 0.25, 1e-6, "halfspace source")
    fails("must be >= 0 for a plane feature", hovox.ags,
          {feature = hovox.plane{normal = {1, 0, 0}}, ranges = {-5, 10, 0}, ms = {1, 0}, me = {0, 1}})
end
near(hovox.point{1, 1, 1}:distance{1, 1, 3}, 2, 1e-12, "point")
near(hovox.point{point = {1, 1, 1}}:distance{1, 1, 3}, 2, 1e-12, "point table")
near(hovox.segment{from = {0, 0, 0}, to = {10, 0, 0}}:distance{15, 3, 4}, math.sqrt(25 + 25), 1e-12, "segment")
local contour = m:contour()
assert(tostring(contour):find("contour"))
near(contour:distance({10, 5, 5}, m), 5, 0.6, "contour depth")
local bottom = hovox.facets(box, {normal = {0, 0, -1}, angle = 5})
near(bottom:distance({10, 5, 4}, m), 4, 0.6, "facet group distance")
local mask = m:mask("surface")
near(mask:distance({10, 5, 5}, m), 4.5, 0.6, "mask distance")
fails("direction must not be zero", hovox.axis, {direction = {0, 0, 0}})
fails("voxel features need the model", contour.distance, contour, {1, 1, 1})
fails("no bool grid 'nope'", m.mask, m, "nope")
fails("picks no facet", hovox.facets, box, {normal = {1, 1, 1}, angle = 1})
-- the harmonic field between the box's x faces is linear along the bar (within a voxel)
local phi = m:harmonic(box, {normal = {-1, 0, 0}, angle = 5}, {normal = {1, 0, 0}, angle = 5})
for _, x in ipairs{2, 5, 10, 15, 18} do near(phi:distance({x, 5, 5}, m), 1 - x / 20, 0.02, "harmonic at x = " .. x) end
fails("picks no facet", m.harmonic, m, box, {normal = {1, 1, 1}, angle = 1}, {normal = {1, 0, 0}, angle = 5})

-- Wu's 3-material paradigm (eq. 13): P = [f, 1 - f - c, c], f within [0, 1 - c]
local w3 = hovox.wu3{feature = hovox.point{0, 0, 0}, d_grad = 10, f = "0.5*d/dg", c = 0.2}
local w3p = w3:eval(5)
near(w3p[1], 0.25, 1e-6, "wu3 f")
near(w3p[2], 0.55, 1e-6, "wu3 1 - f - c")
near(w3p[3], 0.2, 1e-6, "wu3 c")
fails("leaves [0, 0.8]", hovox.wu3, {feature = hovox.point{0, 0, 0}, d_grad = 10, f = "d/dg", c = 0.2})

-- sources
local src = hovox.ags{feature = axis, d_neg = 1, d_grad = 4, d_pos = 0, f = "d/dg",
                      ms = {1, 0, 0}, me = {0, 1, 0}, name = "radial"}
local p = src:eval(3)
near(p[1], 0.5, 1e-6, "eval")
near(p[1] + p[2] + p[3], 1, 1e-12, "sum")
local a, b, c = src:ranges()
assert(a == 1 and b == 4 and c == 0)
near(src:moved(2):eval(3)[1], 0.75, 1e-6, "moved")
local calls = 0
local luaf = hovox.ags{feature = axis, d_grad = 2, ms = {1, 0, 0}, me = {0, 0, 1},
                       f = function(d) calls = calls + 1; return (d / 2) ^ 2 end}
near(luaf:eval(1)[3], 0.25, 1e-5, "lua f")
assert(calls == 4097, "a Lua f is tabulated once: " .. calls .. " calls")
near(hovox.ags{feature = axis, d_grad = 2, ms = {1, 0, 0}, me = {0, 1, 0}, f = {kind = "smoothstep"}}:eval(1)[2],
     0.5, 1e-6, "smoothstep")
near(hovox.ags{feature = axis, d_grad = 4, ms = {1, 0, 0}, me = {0, 1, 0},
               f = {kind = "table", points = {{0, 0}, {2, 1}, {4, 1}}}}:eval(1)[2], 0.5, 1e-6, "table f")
near(hovox.ags{feature = axis, d_grad = 10, ms = {1, 0, 0}, me = {0, 1, 0},
               f = {kind = "sine", k = 0.1}}:eval(5)[2], math.sin(0.5), 1e-5, "sine f")
near(hovox.ags{feature = axis, d_grad = 2, ms = {1, 0, 0}, me = {0, 1, 0}, f = {kind = "power", p = 3}}:eval(1)[2],
     0.125, 1e-5, "power f")
local function bad_f(pattern, ftab)
    fails(pattern, hovox.ags, {feature = axis, d_grad = 2, ms = {1, 0, 0}, me = {0, 1, 0}, f = ftab})
end
bad_f("bad argument #1 to 'hovox.ags' (f of kind sine needs k)", {kind = "sine"})
bad_f("f of kind linear takes no p", {kind = "linear", p = 2})
bad_f("kind must be linear, sine, power, smoothstep or table, got 'cubic'", {kind = "cubic"})
bad_f("f of kind table needs points", {kind = "table"})
bad_f("f: points[2] must be a pair of numbers", {kind = "table", points = {{0, 0}, {1}}})
bad_f("f: points must be 2 to 100000 pairs", {kind = "table", points = {{0, 0}}})
bad_f("unknown option 'amplitud'", {kind = "sine", k = 1, amplitud = 2})
bad_f("p must be in (0,", {kind = "power", p = 0})
local step = hovox.ags{feature = axis, d_neg = 2, ms = {1, 0, 0}, me = {0, 1, 0}}
assert(step:eval(1.9)[1] == 1 and step:eval(2)[2] == 1)
fails("d_grad must be in [0, 1000000000], got -1", hovox.ags, {feature = axis, d_grad = -1, ms = {1}, me = {1}})
fails("Ms = [0.5, 0.6] sums to 1.1", hovox.ags, {feature = axis, ms = {0.5, 0.6}, me = {0, 1}})
fails("ms has 2 values and me 3", hovox.ags, {feature = axis, ms = {0, 1}, me = {0, 0, 1}})
fails("feature must be a hovox feature", hovox.ags, {feature = 3, ms = {1}, me = {1}})
fails("f(2) = 1.0017", hovox.ags, {feature = axis, d_grad = 2, f = "0.50085*d", ms = {1, 0}, me = {0, 1}})
fails("f failed", hovox.ags, {feature = axis, d_grad = 2, f = function() error("boom") end, ms = {1, 0}, me = {0, 1}})
fails("unknown name 'x'", hovox.ags, {feature = axis, d_grad = 2, f = "x", ms = {1, 0}, me = {0, 1}})

-- objects and operators
local o = hovox.object(m, mats)
assert(o:voxels() == m:voxels() and #o:regions() == 1)
local added = o:add_ags(src)
assert(added == src)
local s2 = o:add_ags{feature = hovox.plane{normal = {1, 0, 0}}, d_grad = 20, ms = {0, 0, 1}, me = {0, 1, 0}}
assert(o:regions()[1].sources == 2)
o:set_blend("idw", 2)
o:set_blend("nearest")
-- issue 32.17: move returns the moved source, which takes src's place: it can be moved again and
-- deleted; src itself is no longer in the object
local moved = o:move_ags(src, 0.25)
assert(moved ~= src and select(1, moved:ranges()) == 0.25 and select(1, src:ranges()) == 1, "move_ags returns the moved source")
fails("no such grading source", o.delete_ags, o, src)
moved = o:move_ags(moved, 0.5)
assert(select(1, moved:ranges()) == 0.5 and o:regions()[1].sources == 2)
o:delete_ags(s2)
assert(o:regions()[1].sources == 1)
o:delete_ags(moved)
assert(o:regions()[1].sources == 0)
o:add_ags(moved)
o:set_base{0, 0, 1}
-- method calls name the method and count arguments after self, as Lua does
fails("bad argument #1 to 'set_base' (base = [0.5, 0.6, 0] sums to 1.1", function() o:set_base{0.5, 0.6, 0} end)
fails("bad argument #1 to 'add_ags' (d_grad must be in [0, 1000000000], got -1)",
      function() o:add_ags{feature = axis, d_grad = -1, ms = {1, 0, 0}, me = {1, 0, 0}} end)
fails("no such grading source", o.delete_ags, o, s2)
fails("blend must be nearest or idw, got 'magic'", o.set_blend, o, "magic")
local graded = o:evaluate()
local inside, f = graded:probe{10, 5, 6}
assert(inside)
near(f.A + f.B + f.C, 1, 1e-5, "probe sums to one")
near(f[1], f.A, 0, "indexed and named")
-- at distance 1 from the axis (d_neg moved to 0.5, dg 4): w = 0.125
near(f.B, 0.125, 0.02, "moved source at the probe")
local out_inside = graded:probe{100, 100, 100}
assert(not out_inside)
graded:save(tmp .. "/graded.vdb")
local back = hovox.load(tmp .. "/graded.vdb")
local _, fb = back:probe{10, 5, 6}
-- the file holds the fractions as half floats: within 2^-12 of the computed ones, summing to 1
near(fb.B, f.B, 2 ^ -12, "reloaded")
near(fb.A + fb.B + fb.C, 1, 1e-6, "reloaded fractions sum to one")
local prof = graded:profile{from = {0, 5, 5}, to = {20, 5, 5}, samples = 21, csv = tmp .. "/p.csv",
                            plot = tmp .. "/p.png", title = "test"}
assert(#prof.t == 21 and #prof.A == 21 and prof.inside[11])
near(prof.t[21], 20, 1e-9, "profile length")
assert(io.open(tmp .. "/p.csv"):read("l") == "t,x,y,z,inside,A,B,C")
fails("samples must be", graded.profile, graded, {from = {0, 0, 0}, to = {1, 1, 1}, samples = 1})
graded:profile{from = {0, 5, 5}, to = {20, 5, 5}, plot = tmp .. "/p.svg"}
assert(io.open(tmp .. "/p.svg"):read("a"):find("<svg", 1, true), "an SVG plot, as hovox profile --plot writes")
fails("p.gif' has an unknown extension (use .png or .svg)", graded.profile, graded,
      {from = {0, 5, 5}, to = {20, 5, 5}, csv = tmp .. "/q.csv", plot = tmp .. "/p.gif"})
assert(not io.open(tmp .. "/q.csv"), "a refused plot leaves no CSV either")

-- Booleans on one lattice: two boxes overlapping
local b1 = hovox.voxelize(hovox.generate.box{min = {0, 0, 0}, max = {10, 10, 10}}, {voxel_size = 0.5})
local b2 = hovox.voxelize(hovox.generate.box{min = {5, 0, 0}, max = {15, 10, 10}}, {voxel_size = 0.5})
local h1, h2 = hovox.object(b1, mats), hovox.object(b2, mats)
fails("material 1 is 'A' here and 'P'", h1.union, h1,
      hovox.object(b2, hovox.materials{"P", "Q", "R"}))
h1:add_ags{feature = hovox.point{0, 0, 0}, ms = {1, 0, 0}, me = {1, 0, 0}}
h2:add_ags{feature = hovox.point{0, 0, 0}, ms = {0, 1, 0}, me = {0, 1, 0}}
local n1, n2 = h1:voxels(), h2:voxels()
local inter = h1:intersect(h2)
local uni, diff, merged, sub = h1:union(h2), h1:difference(h2), h1:merge(h2), h1:subtract(h2)
assert(#uni:regions() == 3 and #diff:regions() == 2 and #merged:regions() == 1)
assert(uni:voxels() == merged:voxels() and uni:voxels() == n1 + n2 - inter:voxels())
assert(sub:voxels() == n1 - inter:voxels() and diff:voxels() == n1)
local gd = diff:evaluate()
local _, left = gd:probe{2, 5, 5}
local _, overlap = gd:probe{7.5, 5, 5}
assert(left.A > 0.99 and overlap.B > 0.99, "difference: H2's material in the overlap (Wu eq. 29)")
fails("different voxel lattices", h1.union, h1, hovox.object(aniso, mats))

-- contours (Wu 2.4.1): a box with a through hole, 5 mm layers
local holed = hovox.generate.box{min = {0, 0, 0}, max = {40, 30, 20}, hole = 8, segments = 64}
local layers = hovox.contours(holed, {layer_height = 5, output = tmp .. "/holed.svg"})
assert(#layers == 4, "4 layers, got " .. #layers)
near(layers[1].z, 2.5, 1e-9, "first cut at mid-layer")
assert(layers[2].loops == 2 and layers[2].holes == 1 and layers[2].open == 0)
local hole = 64 / 2 * 64 * math.sin(2 * math.pi / 64) -- the 64-gon's area
near(layers[2].area, 1200 - hole, 1e-4, "outer minus hole") -- float vertices
local c = layers[2].contours
local outer, inner = c[1].orientation == 1 and c[1] or c[2], c[1].orientation == 1 and c[2] or c[1]
assert(inner.orientation == -1 and inner.area < 0 and inner.parent > 0 and c[inner.parent] == outer)
assert(#outer.points >= 4 and #outer.points[1] == 2)
assert(io.open(tmp .. "/holed.svg"):read("a"):find("<svg", 1, true))
local cl = hovox.contours(holed, {layer_height = 5, output = tmp .. "/holed.cli", loops = false})
assert(cl[1].contours == nil and io.open(tmp .. "/holed.cli"):read("l"):find("$$HEADERSTART", 1, true))
assert(#hovox.contours(holed, {adaptive = {1, 5}}) >= 4)
fails("layer_height must be in [0.0001, 100] mm, got 0", hovox.contours, holed, {layer_height = 0})
fails("has an unknown extension (use .svg or .cli)", hovox.contours, holed, {layer_height = 1, output = tmp .. "/x.txt"})
fails("binary needs a .cli output", hovox.contours, holed, {layer_height = 5, binary = true, output = tmp .. "/b.svg"})
fails("the mesh is 20 mm high: no layer of 50 mm has its middle inside it", hovox.contours, holed, {layer_height = 50})
-- one SVG per layer, the same job as `hovox contours --per-layer`
hovox.contours(holed, {layer_height = 5, per_layer = tmp .. "/holed_layers", loops = false})
for i = 0, 3 do
  local f = assert(io.open(string.format("%s/holed_layers/layer-%05d.svg", tmp, i)))
  assert(f:read("a"):find('data-index="0"', 1, true), "a per-layer SVG holds its one layer")
  f:close()
end
assert(not io.open(tmp .. "/holed_layers/layer-00004.svg"), "4 layers, 4 files")

-- export (VTK)
local ex = graded:export{path = tmp .. "/g.vti"}
assert(ex.arrays:find("fraction.A", 1, true) and ex.points > 0 and ex.bytes > 0)
assert(ex.notes:find("density", 1, true), "density is left out: only A defines it")
local exu = graded:export{path = tmp .. "/g.vtu", coarsen = 2, keep = "any", properties = "none"}
assert(exu.cells > 0 and not exu.arrays:find("voigt", 1, true))
fails("path is required", graded.export, graded, {})
fails("keep must be majority or any", graded.export, graded, {path = tmp .. "/x.vtu", keep = "some"})
-- export (3MF Volumetric) and read back: the same voxels, fractions within a 16-bit step
local e3 = graded:export{path = tmp .. "/g.3mf", volumetric = true, bits = 16, properties = "none"}
assert(e3.points > 0 and e3.cells > 0 and e3.arrays == "A,B,C" and e3.bytes > 0, e3.arrays)
local back = hovox.load(tmp .. "/g.3mf")
assert(back:voxels("occupancy") == graded:voxels("occupancy"))
local bin, bfr = back:probe{5, 5, 5}
local gin3, gfr3 = graded:probe{5, 5, 5}
assert(bin == gin3 and math.abs(bfr.A - gfr3.A) <= 1 / 65535 + 1e-6, "3MF fractions back within a step")
fails("bits must be 8 or 16, got 12", graded.export, graded, {path = tmp .. "/x.3mf", volumetric = true, bits = 12})
fails("bits applies to .3mf output only", graded.export, graded, {path = tmp .. "/x.vti", bits = 16})

-- render
graded:render{path = tmp .. "/r.png", size = {64, 48}, surface = true, clip = {"x>10", "z<2"}, view = "top"}
graded:render{path = tmp .. "/v.png", size = {32, 32}, clip_box = {0, 0, 0, 5, 5, 5}, background = "transparent",
              eye = {40, 40, 40}, target = {10, 5, 5}, flat = true, aa = 2}
assert(io.open(tmp .. "/r.png", "rb"):read(4) == "\137PNG")
fails("path is required", graded.render, graded, {})
fails("clip", graded.render, graded, {path = tmp .. "/x.png", clip = "w>3"})
fails("size must be", graded.render, graded, {path = tmp .. "/x.png", size = {0, 5}})
fails("unknown option 'sise'", graded.render, graded, {path = tmp .. "/x.png", sise = {8, 8}})
fails("unknown option 'coarse'", graded.export, graded, {path = tmp .. "/x.vtu", coarse = 2})
fails("view and eye exclude each other", graded.render, graded, {path = tmp .. "/x.png", view = "top", eye = {1, 2, 3}})
fails("target needs eye", graded.render, graded, {path = tmp .. "/x.png", target = {1, 2, 3}})

-- an object renders, exports, probes, profiles, saves and slices through an evaluation, with
-- its errors named as its own
o:render{path = tmp .. "/o.png", size = {16, 16}}
assert(io.open(tmp .. "/o.png", "rb"):read(4) == "\137PNG")
assert(o:export{path = tmp .. "/o.vti"}.bytes == graded:export{path = tmp .. "/g2.vti"}.bytes)
local oin, ofr = o:probe{5, 5, 5}
local gin, gfr = graded:probe{5, 5, 5}
assert(oin == gin and ofr[1] == gfr[1] and ofr[2] == gfr[2], "object and model probe alike")
o:save(tmp .. "/o.vdb")
assert(hovox.load(tmp .. "/o.vdb"):grids()[1])
fails("bad argument #1 to 'render' (table expected", o.render, o, 5)
fails("bad argument #1 to 'probe'", function() return o:probe(1, 2, 3) end)
fails("test_api.lua:", function() return o:probe(1, 2, 3) end)

-- printer layers (Wu 2.4.2): the 20 x 10 x 10 box at 0.5 mm pixels (plus a 2-pixel margin) and
-- 1 mm layers; a layer exists while its mid-height is inside the mesh
local st = graded:layers{mesh = box, dir = tmp .. "/stack", dpi = {50.8, 50.8}, layer_height = 1, compare = true}
assert(st.width == 44 and st.height == 24 and st.layers == 10 and st.first == 0 and st.last == 10,
       string.format("%d x %d x %d", st.width, st.height, st.layers))
assert(st.object_pixels == 40 * 20 * 10, "every pixel of the box: " .. st.object_pixels)
for _, k in ipairs{"A", "B", "C"} do
    near(st.materials[k].achieved, st.materials[k].target, 0.02, "halftone keeps the mean of " .. k)
end
assert(st.diff_mean >= 0 and st.diff_max < 0.2, "resample vs direct: " .. st.diff_max)
assert(io.open(tmp .. "/stack/layer-00009.png", "rb"):read(4) == "\137PNG")
assert(io.open(tmp .. "/stack/manifest.json"):read("a"):find('"layers_total": 10', 1, true))
local fr = graded:layers{mesh = box, dir = tmp .. "/fr", dpi = {25.4, 25.4}, layer_height = 2,
                         mode = "fractions", method = "direct", layers = {1, 3}}
assert(fr.first == 1 and fr.last == 3 and fr.layers == 5 and fr.width == 24)
assert(io.open(tmp .. "/fr/B/layer-00002.png", "rb") and not io.open(tmp .. "/fr/B/layer-00000.png", "rb"))
local mk = graded:layers{mesh = box, dir = tmp .. "/mask", profile = "j750", mode = "mask", layers = {0, 2},
                         gcvf = tmp .. "/mask.zip"}
assert(mk.width == math.ceil(20 / (25.4 / 600)) + 4 and mk.layers == math.floor(10 / 0.027 + 0.5), mk.width .. " " .. mk.layers)
assert(io.open(tmp .. "/mask.zip", "rb"):read(2) == "PK")
fails("a stack exists there", graded.layers, graded, {mesh = box, dir = tmp .. "/stack", profile = "j750"})
graded:layers{mesh = box, dir = tmp .. "/stack", profile = "j750", layers = {5, 6}, force = true}
fails("profile must be a printer profile (j750, j850, or dpi with layer_height), got 'x'", graded.layers, graded, {mesh = box, dir = tmp .. "/y", profile = "x"})
fails("mode must be halftone, fractions or mask, got 'gray'", graded.layers, graded, {mesh = box, dir = tmp .. "/y", profile = "j750", mode = "gray"})
fails("dir is required", graded.layers, graded, {mesh = box, profile = "j750"})
fails("dpi needs layer_height", graded.layers, graded, {mesh = box, dir = tmp .. "/y", dpi = {600, 300}})
fails("profile and dpi exclude each other", graded.layers, graded,
      {mesh = box, dir = tmp .. "/y", dpi = {600, 300}, layer_height = 1, profile = "j750"})

-- explicit freeing
gd:free()
fails("object was freed", gd.voxels, gd)
collectgarbage()
-- trays: the graded box (materials A, B, C) twice and a plain box, arranged; a layer range
box:save(tmp .. "/tray_box.stl")
graded:save(tmp .. "/tray_graded.vdb")
local tray = hovox.tray{resin = {A = "VeroCyan-V", B = "VeroMagenta-V", C = "VeroYellow-V"}, mode = "halftone"}
assert(tray:add{model = tmp .. "/tray_graded.vdb", mesh = tmp .. "/tray_box.stl", copies = 2} == 1)
assert(tray:add{mesh = tmp .. "/tray_box.stl", material = "VeroPureWhite", rotation = 90} == 2)
local plan = tray:arrange{spacing = 4}
assert(plan.parts == 3 and plan.width == 11575 and plan.height == 4606 and plan.resins == 4, plan.resins)
assert(plan.layers == 370 and plan.utilisation > 0.003 and plan.utilisation < 0.01, plan.layers)
local wrote = tray:layers{dir = tmp .. "/tray", layers = {100, 102}}
assert(wrote.first == 100 and wrote.last == 102 and wrote.object_pixels > 0 and wrote.bytes > 0)
assert(io.open(tmp .. "/tray/layer-00101.png") and io.open(tmp .. "/tray/manifest.json"))
fails("rotation must be 0, 90, 180 or 270, got 45", tray.add, tray, {mesh = tmp .. "/tray_box.stl", material = "X",
                                                                       rotation = 45})
fails("unknown option 'rot'", tray.add, tray, {mesh = tmp .. "/tray_box.stl", rot = 90})
fails("mode must be halftone or mask, got 'gray'", tray.layers, tray, {dir = tmp .. "/t2", mode = "gray"})
-- issue 18: a calibration table given as a table, property targets (log), and a field feature
-- read back from a .vti this script exports (the rigid fraction, so d = f of the first grading)
local cal = {property = "youngs_modulus", unit = "MPa", points = {{0, 0.6}, {0.5, 9.5}, {0.8, 250}, {1, 2000}}}
local psrc = hovox.ags{feature = hovox.plane{point = {0, 0, 0}, normal = {1, 0, 0}}, ranges = {0, 10, 0},
                       ms = {0, 1}, me = {1, 0}, calibration = cal, property_grading = "youngs_modulus",
                       ps = "1MPa", pe = "1GPa", log = true}
local t_mid = psrc:eval(5)[1] -- P = sqrt(1 * 1000) MPa = 31.62 MPa: t = 0.5 + (31.62 - 9.5) / 240.5 * 0.3
assert(math.abs(t_mid - (0.5 + (math.sqrt(1000) - 9.5) / 240.5 * 0.3)) < 1e-5, t_mid)
-- plain numbers are values in the table's unit, as the CLI reads --ps 1 --pe 1000
local nsrc = hovox.ags{feature = hovox.plane{point = {0, 0, 0}, normal = {1, 0, 0}}, ranges = {0, 10, 0},
                       ms = {0, 1}, me = {1, 0}, calibration = cal, property_grading = "youngs_modulus",
                       ps = 1, pe = 1000, log = true}
collectgarbage() -- the texts made from the numbers must outlive the call that read them
assert(nsrc:eval(5)[1] == t_mid, "ps = 1, pe = 1000 (MPa) grade as '1MPa', '1GPa'")
fails("Pe = 3000 MPa is outside the calibration table's youngs_modulus range [0.6, 2000] MPa", hovox.ags,
      {feature = hovox.plane{point = {0, 0, 0}, normal = {1, 0, 0}}, ranges = {0, 10, 0}, ms = {0, 1}, me = {1, 0},
       calibration = cal, property_grading = "youngs_modulus", ps = "1MPa", pe = "3GPa"})
fails("row 3: youngs_modulus 5 is not greater than row 2's (9.5)", hovox.ags,
      {feature = hovox.plane{point = {0, 0, 0}, normal = {1, 0, 0}}, ranges = {0, 10, 0}, ms = {0, 1}, me = {1, 0},
       calibration = {property = "youngs_modulus", points = {{0, 1}, {0.5, 9.5}, {1, 5}}}})
local bar = hovox.voxelize(hovox.generate.box{sx = 20, sy = 4, sz = 4}, {voxel_size = 0.5})
local bobj = hovox.object(bar, hovox.materials{"rigid", "rubber"})
bobj:add_ags{feature = hovox.plane{point = {-10, 0, 0}, normal = {1, 0, 0}}, ranges = {0, 20, 0},
             ms = {0, 1}, me = {1, 0}}
local bg = bobj:evaluate()
bg:export{path = tmp .. "/bar.vti"}
local ffeat, frep = bar:field{file = tmp .. "/bar.vti", array = "fraction.rigid"}
assert(frep.filled == 0 and frep.lo >= 0 and frep.hi <= 1 and frep.voxels == bar:voxels(), frep.filled)
assert(math.abs(ffeat:distance({0.25, 0.25, 0.25}, bar) - 10.25 / 20) < 1e-4)
fails("no array 'sigma'", bar.field, bar, {file = tmp .. "/bar.vti", array = "sigma"})
-- the property along a profile: the table at the t the grading gives (t = (x + 10) / 20 on this bar)
local pobj = hovox.object(bar, hovox.materials{"rigid", "rubber"})
pobj:add_ags{feature = hovox.plane{point = {-10, 0, 0}, normal = {1, 0, 0}}, ranges = {0, 20, 0},
             ms = {0, 1}, me = {1, 0}, calibration = cal}
local pg = pobj:evaluate()
local pp = pg:profile{from = {0.25, 1.25, 1.25}, to = {9.75, 1.25, 1.25}, samples = 20, property = "youngs_modulus"}
assert(pp.property.name == "youngs_modulus" and pp.property.unit == "MPa" and #pp.property.values == 20)
for i = 1, 20 do
    local t = (0.25 + (i - 1) * 0.5 + 10) / 20 -- 0.5125 .. 0.9875: rows (0.5, 9.5), (0.8, 250), (1, 2000)
    local want = t <= 0.8 and 9.5 + (t - 0.5) / 0.3 * 240.5 or 250 + (t - 0.8) / 0.2 * 1750
    assert(math.abs(pp.property.values[i] - want) < 1e-4 * want,
           string.format("sample %d: %g, want %g", i, pp.property.values[i], want))
end
fails("no calibration table for youngs_modulus in the model's grading definition (it has no calibration tables)",
      bg.profile, bg, {from = {-5, 0, 0}, to = {5, 0, 0}, property = "youngs_modulus"})
-- a field the script computes goes out through the export path and comes back as a feature
assert(bar:add_grid("x2y", function(x, y, z) return x + 2 * y end) == bar:voxels("occupancy"))
for _, grid in ipairs(bar:grids()) do -- one spelling per type, hv_grid_type_name's (issue 26 item 5)
  if grid.name == "x2y" then assert(grid.type == "float", grid.type) end
end
bar:export{path = tmp .. "/x2y.vti", grids = "x2y", properties = "none"}
local xf = bar:field{file = tmp .. "/x2y.vti", array = "x2y"}
assert(math.abs(xf:distance({1.25, 0.75, 0.25}, bar) - (1.25 + 1.5)) < 1e-5)
-- .vtu: cell data averaged over a 2 x 2 x 2 block: the linear field's value at the block's centre
bar:export{path = tmp .. "/x2y.vtu", grids = "x2y", properties = "none", coarsen = 2}
local xu = bar:field{file = tmp .. "/x2y.vtu", array = "x2y", outside = "nearest"}
-- voxel (1.25, 0.75, 0.25) is index (2, 1, 0) (centres at 0.25 + 0.5 i); its block spans indices 2..3, 0..1, 0..1,
-- centres x 1.25, 1.75 and y 0.25, 0.75: the average is 1.5 + 2 * 0.5
assert(math.abs(xu:distance({1.25, 0.75, 0.25}, bar) - 2.5) < 1e-5, xu:distance({1.25, 0.75, 0.25}, bar))
fails("grid 'bad': the value at", bar.add_grid, bar, "bad", function() return 0 / 0 end)
fails("add_grid: the function returned string", bar.add_grid, bar, "s", function() return "x" end)
fails("export: the model has no float grid 'nope' (float grids: x2y)", bar.export, bar,
      {path = tmp .. "/nope.vti", grids = "nope"})
print("test_api.lua: all checks passed")
