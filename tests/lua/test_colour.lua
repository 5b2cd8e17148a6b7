-- tests/lua/test_colour.lua - full colour from Lua (issue 29): mesh:set_colour gives a body one
-- colour, model:paint paints the model as `voxelize --colour-depth` does (the same fractions as
-- the CLI's model, the core beneath), and the refusals (a bad colour, a body not there, a mesh
-- without colour, a profile that is not ICC, a bad depth) name what is wrong.
-- Run: hovox run tests/lua/test_colour.lua TMPDIR SHARED
local tmp = arg[1]
assert(tmp, "usage: test_colour.lua TMPDIR [SHARED]")
local function fails(pattern, fn, ...)
    local ok, err = pcall(fn, ...)
    assert(not ok, "expected an error matching " .. pattern)
    assert(tostring(err):find(pattern, 1, true), "error '" .. tostring(err) .. "' lacks '" .. pattern .. "'")
end

local box = hovox.generate.box{min = {0, 0, 0}, max = {6, 6, 6}}
local model = hovox.voxelize(box, {voxel_size = 0.5})
fails("no colour to paint", model.paint, model, box, {colour_depth = 1})
fails("is not #rrggbb", box.set_colour, box, "body 1", "#12")
local body = box:bodies()[1].name
fails("no body 'hub'", box.set_colour, box, "hub", "#ff0000")
assert(box:set_colour(body, "#ff0000") == box)
local f = io.open(tmp .. "/x.icc", "w")
f:write("not a profile")
f:close()
fails("not an ICC profile", model.paint, model, box, {icc = tmp .. "/x.icc"})
fails("colour_depth must be", model.paint, model, box, {colour_depth = -1})
fails("unknown option 'depth'", model.paint, model, box, {depth = 1})
assert(model:paint(box, {colour_depth = 1, core = "Agilus30", intent = "relative"}) == model)
-- the skin: red as `hovox colour '#ff0000' --intent relative` gives it; the centre: the core
local _, skin = model:probe{3, 3, 0.25}
local _, core = model:probe{3, 3, 3}
assert(math.abs(skin["VeroMagenta-V"] - skin["VeroYellow-V"]) < 0.05, "red is as much magenta as yellow")
assert(skin["VeroMagenta-V"] > 0.4 and skin.Agilus30 == 0, "the skin is red")
assert(core.Agilus30 == 1, "the core is Agilus30")
-- painted twice: the grids are there already
fails("already", model.paint, model, box, {colour_depth = 1, core = "Agilus30"})
-- the stack reports the skin's dE2000
local st = model:layers{mesh = box, dir = tmp .. "/stack", profile = "j750", layers = {40, 41}}
assert(st.colour and st.colour.skin_voxels > 0 and st.colour.mean_de2000_target > 1, "stack colour report")
-- hovox.colour: what `hovox colour` prints (red through the default profile: half magenta, half
-- yellow, dE2000 20.97)
local red = hovox.colour("#ff0000")
assert(math.abs(red["VeroMagenta-V"] - 0.5) < 0.01 and math.abs(red["VeroYellow-V"] - 0.5) < 0.01, "red's fractions")
assert(math.abs(red.de2000 - 20.97) < 0.01, "red's dE2000 " .. red.de2000)
local rel = hovox.colour("1,1,0", {resins = "C1,M1,Y1,K1,W1,Clear1", intent = "relative"})
assert(rel.Y1 > 0.5 and rel["VeroYellow-V"] == nil, "another resin map")
fails("is not #rrggbb", hovox.colour, "#ff00")
fails("not an ICC profile", hovox.colour, "#ff0000", {icc = tmp .. "/x.icc"})
print("colour: ok")
