-- tests/lua/test_assembly.lua - assemblies from Lua: meshes joined into bodies, saved as OBJ,
-- voxelized into regions, graded per region, sliced per body, printed from the multi-body mesh.
-- Run: hovox run tests/lua/test_assembly.lua TMPDIR SHARED
local tmp = arg[1]
assert(tmp, "usage: test_assembly.lua TMPDIR [SHARED]")
local function fails(pattern, fn, ...)
    local ok, err = pcall(fn, ...)
    assert(not ok, "expected an error matching " .. pattern)
    assert(tostring(err):find(pattern, 1, true), "error '" .. tostring(err) .. "' lacks '" .. pattern .. "'")
end

local outer = hovox.generate.box{min = {0, 0, 0}, max = {10, 10, 10}}
local inner = hovox.generate.box{min = {3, 3, 3}, max = {7, 7, 7}}

-- joining
local a = hovox.join_meshes{{mesh = inner, name = "core", material = "Agilus"},
                            {mesh = outer, name = "shell", material = "Vero"}}
assert(a:count() == 24)
assert(a:report().volume == 64 + 1000)
a:save(tmp .. "/assembly.obj")
local f = assert(io.open(tmp .. "/assembly.obj"))
local text = f:read("a")
f:close()
assert(text:find("\no core\nusemtl Agilus\n", 1, true) and text:find("\no shell\nusemtl Vero\n", 1, true))
assert(hovox.join_meshes{{mesh = outer}}:count() == 12)
fails("give at least one part", hovox.join_meshes, {})
fails("unknown key 'materia'", hovox.join_meshes, {{mesh = outer, materia = "x"}})
fails("part 1: mesh must be a hovox mesh", hovox.join_meshes, {{name = "x"}})
fails("part 2 must be a plain table", hovox.join_meshes, {{mesh = outer}, "shell"})
local gone = hovox.generate.box{min = {0, 0, 0}, max = {1, 1, 1}}
gone:free()
fails("object was freed", function() return gone:count() end)

-- voxelizing: one region per body, a voxel to the body holding its centre, the first keeping
-- the overlap: the 4 mm core's 8^3 centres (its outward surface voxels, 488 of its 1000, go to the
-- solid 10 mm box around it, whose centres overlap the core's 512)
local m = hovox.voxelize(a, {voxel_size = 0.5})
local rg = m:regions()
assert(#rg == 2 and rg[1].name == "core" and rg[2].name == "shell")
assert(rg[1].material == "Agilus" and rg[1].grid == "region.core" and rg[1].fill == "flood")
assert(rg[1].voxels == 512 and rg[1].lost == 488 and next(rg[1].lost_to) == nil)
assert(rg[2].lost == 512 and rg[2].lost_to.core == 512)
assert(m:voxels("region.core") == 512)
assert(m:voxels() == rg[1].voxels + rg[2].voxels)
assert(#hovox.voxelize(outer, {voxel_size = 0.5}):regions() == 0)
local first = hovox.voxelize(hovox.join_meshes{{mesh = outer, name = "shell", material = "Vero"},
                                               {mesh = inner, name = "core", material = "Agilus"}}, {voxel_size = 0.5})
assert(first:regions()[2].voxels == 0 and first:regions()[2].lost == 1000 and first:regions()[2].lost_to.shell == 512)

-- objects: regions named after the bodies, bases from their materials
local o = hovox.object(m)
local names = o:materials():names()
assert(#names == 2 and names[1] == "Agilus" and names[2] == "Vero")
local r = o:regions()
assert(r[1].name == "core" and r[1].base[1] == 1 and r[1].base[2] == 0)
assert(r[2].name == "shell" and r[2].base[2] == 1)
local g = o:evaluate()
local inside, fr = g:probe{5, 5, 5}
assert(inside and fr.Agilus == 1 and fr.Vero == 0)
inside, fr = g:probe{1, 1, 1}
assert(inside and fr.Agilus == 0 and fr.Vero == 1)
-- a source in the core alone
o:add_ags({feature = hovox.point{5, 5, 5}, ranges = {0, 2, 0}, ms = {0, 1}, me = {1, 0}}, "core")
r = o:regions()
assert(r[1].sources == 1 and r[2].sources == 0)
fails("the object has no region 'mantle' (regions: core, shell)", o.add_ags, o,
      {feature = hovox.point{5, 5, 5}, ranges = {0, 2, 0}, ms = {0, 1}, me = {1, 0}}, "mantle")
g = o:evaluate()
inside, fr = g:probe{1, 1, 1}
assert(fr.Vero == 1)
inside, fr = g:probe{6.25, 5.25, 5.25}
assert(fr.Agilus > 0.2 and fr.Agilus < 1, "graded core: " .. fr.Agilus)
o:set_base({0.5, 0.5}, "shell")
assert(o:regions()[2].base[1] == 0.5)
fails("the object has no region 'x'", o.set_base, o, {1, 0}, "x")
g:save(tmp .. "/graded.vdb")
local back = hovox.load(tmp .. "/graded.vdb")
assert(#back:regions() == 2)
-- a list given must name every body's material; its order is the table's
local mats = hovox.materials{"Vero", "Agilus", "Support"}
local o2 = hovox.object(m, mats)
assert(o2:materials():names()[3] == "Support" and o2:regions()[1].base[2] == 1)
fails("region 'core' is material Agilus, which the materials given (A, B) do not name", hovox.object, m,
      hovox.materials{"A", "B"})
-- a grid named: one region, as before
assert(#hovox.object(m, mats, {grid = "occupancy"}):regions() == 1)
fails("materials are required", hovox.object, hovox.voxelize(outer, {voxel_size = 1}))

-- contours per body, layers from the multi-body mesh
local layers = hovox.contours(a, {layer_height = 2})
assert(#layers == 5 and layers[3].loops == 2)
local bodies = {}
for _, c in ipairs(layers[3].contours) do bodies[c.body] = c.area end
assert(bodies.core == 16 and bodies.shell == 100)
local rep = g:layers{mesh = a, dir = tmp .. "/stack", dpi = {50, 50}, layer_height = 1, layers = {4, 6}}
assert(rep.materials.Agilus.achieved > 0 and rep.materials.Vero.achieved > 0)

-- a body's material given in the script (issue 27 item 2), as voxelize --material BODY=MATERIAL
local named = hovox.join_meshes{{mesh = inner, name = "core"}, {mesh = outer, name = "shell", material = "Vero"}}
assert(named:set_material("core", "Agilus") == named)
local bm = named:bodies()
assert(bm[1].material == "Agilus" and bm[2].material == "Vero")
fails("no body 'hub' (bodies: core, shell)", named.set_material, named, "hub", "Vero")

print("test_assembly.lua: all checks passed")
