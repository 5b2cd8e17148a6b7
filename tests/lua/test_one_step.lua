-- tests/lua/test_one_step.lua - a mesh to a stack in one step from Lua (issue 27 items 1-3):
-- mesh:layers{...} prints a part in its bodies' materials as `hovox layers PART.3mf` does (CLI case
-- layers_lua_one_step compares the bytes), materials = {BODY = MATERIAL} names a body's material
-- (tray:add takes the same key), and a mesh whose size suggests a wrong unit is warned about in
-- the report, naming the unit. Run: hovox run tests/lua/test_one_step.lua TMPDIR SHARED
local tmp, shared = arg[1], arg[2] or "tests/data"
assert(tmp, "usage: test_one_step.lua TMPDIR [SHARED]")
local function fails(pattern, fn, ...)
    local ok, err = pcall(fn, ...)
    assert(not ok, "expected an error matching " .. pattern)
    assert(tostring(err):find(pattern, 1, true), "error '" .. tostring(err) .. "' lacks '" .. pattern .. "'")
end
local function read(path)
    local f = assert(io.open(path, "rb"))
    local s = f:read("a")
    f:close()
    return s
end

local part = hovox.load_mesh(shared .. "/good/core_in_shell.3mf")
local r = part:layers{dir = tmp .. "/a", layers = {180, 184}, materials = {core = "Agilus30Black"}}
assert(r.first == 180 and r.last == 184 and r.layers == 370 and r.warnings == "", r.warnings)
assert(r.width == 241 and r.height == 123 and r.object_pixels > 0)
local man = read(tmp .. "/a/manifest.json")
assert(man:find('"name": "Agilus30Black"', 1, true) and man:find('"name": "VeroWhite"', 1, true), man)
assert(part:bodies()[2].material == "Agilus30") -- the mesh itself keeps the file's materials
-- the same materials given by mesh:set_material on a copy: the same bytes
local copy = part:transform{}
copy:set_material("core", "Agilus30Black")
copy:layers{dir = tmp .. "/b", layers = {180, 184}}
for _, f in ipairs{"manifest.json", "layer-00180.png", "layer-00183.png"} do
    assert(read(tmp .. "/a/" .. f) == read(tmp .. "/b/" .. f), f)
end
-- a coarser voxel size is taken, and mask mode makes no model
part:layers{dir = tmp .. "/c", layers = {180, 181}, voxel_size = 0.5}
local m = part:layers{dir = tmp .. "/d", mode = "mask", layers = {180, 181}}
assert(m.object_pixels > 0)
-- refused: a body the mesh lacks, a bad pair, an unknown key, no dir; nothing written
fails("no body 'cor' (bodies: shell, core)", part.layers, part, {dir = tmp .. "/x", materials = {cor = "A"}})
fails("materials.core must be a string", part.layers, part, {dir = tmp .. "/x", materials = {core = 3}})
fails("unknown option 'voxel_sise'", part.layers, part, {dir = tmp .. "/x", voxel_sise = 1})
fails("dir is required", part.layers, part, {})
assert(not io.open(tmp .. "/x/manifest.json"))

-- size warnings: a 0.2 mm box says which unit would make it printable; in metres it says nothing
local tiny = hovox.generate.box{min = {0, 0, 0}, max = {0.2, 0.1, 0.05}}
local w = tiny:layers{dir = tmp .. "/tiny", mode = "mask"}.warnings
assert(w:find("is 0.2 x 0.1 x 0.05 mm, smaller than 1 mm: if its unit is metres, unit m makes it 200 mm across",
              1, true), w)
assert(tiny:transform{unit = "m"}:layers{dir = tmp .. "/big", mode = "mask", layers = {0, 1}}.warnings == "")

-- a tray part: materials = {BODY = MATERIAL} and the size warning in the plan's report
tiny:save(tmp .. "/tiny.stl")
local t = hovox.tray{profile = "j750", mode = "mask"}
t:add{mesh = shared .. "/good/core_in_shell.3mf", materials = {shell = "VeroCyan-V", core = "Agilus30Black"},
      at = {40, 40}}
t:add{mesh = tmp .. "/tiny.stl", material = "VeroPureWhite", at = {100, 100}}
local plan = t:arrange{arrange = "no"}
assert(plan.parts == 2 and plan.warnings:find("part 2 (tiny.stl): ", 1, true)
       and plan.warnings:find("unit m makes it 200 mm across", 1, true), plan.warnings)
fails("materials gives each body its material", t.add, t,
      {mesh = tmp .. "/tiny.stl", material = "VeroPureWhite", materials = {tiny = "VeroCyan-V"}})
print("one step: ok")
