-- tests/lua/test_placement.lua - units and transforms from Lua (issue 27 item 3): mesh:transform{...}
-- places as the CLI's --unit, --up, --scale, --rotate, --translate do, and tray parts take the
-- same keys. Run: hovox run tests/lua/test_placement.lua TMPDIR SHARED
local tmp = arg[1]
assert(tmp, "usage: test_placement.lua TMPDIR [SHARED]")
local function fails(pattern, fn, ...)
    local ok, err = pcall(fn, ...)
    assert(not ok, "expected an error matching " .. pattern)
    assert(tostring(err):find(pattern, 1, true), "error '" .. tostring(err) .. "' lacks '" .. pattern .. "'")
end
local function near(a, b) return math.abs(a - b) < 1e-4 end
local function box_is(m, lo, hi)
    local b = m:report().bbox
    for k = 1, 3 do
        assert(near(b.min[k], lo[k]) and near(b.max[k], hi[k]),
               string.format("axis %d: %g..%g, want %g..%g", k, b.min[k], b.max[k], lo[k], hi[k]))
    end
end

-- a 30 x 20 x 10 box in cm, Y-up: in mm, Z-up, 300 x 100 x 200 (y -100..0)
local box = hovox.generate.box{min = {0, 0, 0}, max = {30, 20, 10}}
box_is(box:transform{unit = "cm", up = "y"}, {0, -100, 0}, {300, 0, 200})
-- the keys' order does not matter: unit, up, scale, rotations (in list order), translate
local placed = box:transform{translate = {1, 2, 3}, rotate = {"z:90", "x:90"}, scale = 2}
-- scale 2: 60 x 40 x 20; z:90: x -40..0, y 0..60; x:90: y -20..0, z 0..60; + (1, 2, 3)
box_is(placed, {-39, -18, 3}, {1, 2, 63})
assert(near(placed:report().volume, 8 * box:report().volume))
box_is(box:transform{rotate = "30@0,0,1"}, {-10, 0, 0}, {30 * math.cos(math.pi / 6), 30 * 0.5 + 20 * math.cos(math.pi / 6), 10})
box_is(box:transform{}, {0, 0, 0}, {30, 20, 10}) -- nothing given: a copy
assert(box:report().bbox.max[1] == 30) -- the mesh itself is not moved
fails("unit must be one of mm, cm, m, in, ft, um, got 'parsec'", box.transform, box, {unit = "parsec"})
fails("rotate must be AXIS:DEGREES", box.transform, box, {rotate = "w:1"})
fails("scale must be S or SX,SY,SZ", box.transform, box, {scale = {1, 0, 1}})
fails("unknown option 'rotation'", box.transform, box, {rotation = 90})

-- a tray part takes the same keys: the box stood up (Y-up) is 20 mm tall, 741 J750 layers
box:save(tmp .. "/box.stl")
local t = hovox.tray{profile = "j750", mode = "mask"}
t:add{mesh = tmp .. "/box.stl", material = "VeroCyan-V", at = {100, 100}, up = "y", rotate = "z:90"}
t:layers{dir = tmp .. "/stack"}
local f = assert(io.open(tmp .. "/stack/manifest.json"))
local text = f:read("a")
f:close()
assert(text:find('"placement": "up y, rotate z:90"', 1, true), text:sub(1, 400))
assert(text:find('"layers_total": 741,', 1, true) and text:find('"box_mm": [95, 85, 105, 115]', 1, true), text)
print("placement: ok")
