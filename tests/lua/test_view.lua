-- tests/lua/test_view.lua - view = true on model:layers and tray:layers writes the stack's page
-- (hovox view) with the stack. Run: hovox run tests/lua/test_view.lua TMPDIR SHARED
local tmp = arg[1]
assert(tmp, "usage: test_view.lua TMPDIR SHARED")
local function fails(pattern, fn, ...)
    local ok, err = pcall(fn, ...)
    assert(not ok, "expected an error matching " .. pattern)
    assert(tostring(err):find(pattern, 1, true), "error '" .. tostring(err) .. "' lacks '" .. pattern .. "'")
end
local function page(dir)
    local f = io.open(dir .. "/index.html")
    if not f then return nil end
    local text = f:read("a")
    f:close()
    return text
end

local box = hovox.generate.box{min = {0, 0, 0}, max = {10, 6, 3}}
local model = hovox.voxelize(box, {voxel_size = 0.5})
local st = model:layers{mesh = box, dir = tmp .. "/stack", dpi = {50, 50}, layer_height = 1, mode = "mask", view = true}
assert(st.layers == 3)
local html = assert(page(tmp .. "/stack"), "no page in the stack")
assert(html:find("<title>stack</title>", 1, true) and html:find('id="hovox-data"', 1, true))
model:layers{mesh = box, dir = tmp .. "/plain", dpi = {50, 50}, layer_height = 1, mode = "mask"}
assert(not page(tmp .. "/plain"), "a page without view")
fails("view must be true or false", model.layers, model,
      {mesh = box, dir = tmp .. "/bad", dpi = {50, 50}, layer_height = 1, mode = "mask", view = "yes"})

box:save(tmp .. "/part.stl")
local tray = hovox.tray{}
tray:add{mesh = tmp .. "/part.stl", material = "VeroPureWhite"}
tray:arrange{}
tray:layers{dir = tmp .. "/tray", layers = {0, 2}, view = true}
html = assert(page(tmp .. "/tray"), "no page in the tray")
assert(html:find('"kind": "tray"', 1, true) and html:find("part.stl", 1, true))
tray:layers{dir = tmp .. "/tray2", layers = {0, 1}}
assert(not page(tmp .. "/tray2"), "view is not remembered between calls")
print("test_view.lua: ok")
