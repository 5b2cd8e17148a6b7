# hostile script against the Lua changes of stop 24: the named copies of the class methods in
# package.loaded (replaced, given metatables that free objects and collect garbage, filled with
# objects), nested-table strings (join_meshes parts, material and calibration tables) whose
# values free objects or carry metatables, an object's model methods whose error text is
# rewritten (paths with quotes and format characters), a path swapped after its check, a link
# out of the output dir, bytecode, and a loop that never ends
mkdir -p "$TMP/out" "$TMP/outside" && ln -s "$TMP/outside" "$TMP/out/escape" && cd "$TMP" || exit 1
cp "$OLDPWD/tests/cli/hostile_prelude.lua" attack.lua # out, try(): lines 1-5
cat >>attack.lua <<'LUA'
local box = hovox.generate.box{min = {0, 0, 0}, max = {10, 10, 10}}
local model = hovox.voxelize(box, {voxel_size = 1})
-- 1. the named copies: a copy whose __index frees the model and collects garbage, then
-- argument errors, whose names Lua looks up in package.loaded (raw reads: no metamethod runs)
local victim = hovox.voxelize(box, {voxel_size = 2})
package.loaded["hovox.Model"] = setmetatable({}, {__index = function() victim:free(); collectgarbage() end,
  __pairs = function() victim:free(); collectgarbage() end})
try("model error, copy replaced", model.render, model, 5)
print("victim alive", pcall(victim.grids, victim) and "yes")
-- a copy stuffed with objects and a huge key set; a copy that is not a table
local stuffed = {}
for i = 1, 20000 do stuffed["k" .. i] = hovox.generate.box{max = {1, 1, 1}} end
package.loaded["hovox.Mesh"] = stuffed
try("mesh error, stuffed copy", box.save, box, 5)
package.loaded["hovox.Object"] = 42
stuffed = nil
collectgarbage()
-- 2. join_meshes: a part name that frees the mesh, a name table with __tostring, a material
-- with __index; refused before any mesh is read
local m2 = hovox.generate.box{max = {2, 2, 2}}
try("part name frees", hovox.join_meshes, {{mesh = m2, name = setmetatable({}, {__tostring = function() m2:free(); collectgarbage(); return "n" end})}})
try("part material table", hovox.join_meshes, {{mesh = m2, material = setmetatable({}, {__index = function() m2:free() end})}})
try("part name NUL", hovox.join_meshes, {{mesh = m2, name = "a\0b"}})
print("m2 alive", pcall(m2.report, m2) and "yes")
-- 3. material and calibration tables whose names are objects or carry metatables
try("material name table", hovox.materials, {{name = setmetatable({}, {__tostring = function() model:free() return "x" end})}})
local axis = hovox.axis{origin = {0, 0, 0}, direction = {0, 0, 1}}
try("calibration property table", hovox.ags, {feature = axis, d_grad = 2, ms = {1, 0}, me = {0, 1},
  calibration = {property = setmetatable({}, {__tostring = function() model:free() return "p" end}), points = {{0, 1}, {1, 2}}}})
try("calibration unit number", hovox.ags, {feature = axis, d_grad = 2, ms = {1, 0}, me = {0, 1},
  calibration = {property = "youngs_modulus", unit = {}, points = {{0, 1}, {1, 2}}}})
-- 4. an object's model methods: the error text is rewritten; paths with quotes and format
-- characters, an options table that frees the object, a path swapped after its check
local mats = hovox.materials{"A", "B"}
local o = hovox.object(model, mats)
o:add_ags(hovox.ags{feature = axis, d_grad = 10, ms = {1, 0}, me = {0, 1}})
try("object render quote path", o.render, o, {path = out .. "/escape/%s'%d'.png"})
try("object render bad size", o.render, o, {path = out .. "/r.png", size = "0x'5"})
try("object render number", o.render, o, 5)
local n = 0
try("object render swapped path", o.render, o, setmetatable({}, {__index = function(t, k)
  n = n + 1; if k == "path" then return n < 3 and out .. "/r.png" or out .. "/escape/r.png" end end}))
try("object render frees", o.render, o, {path = out .. "/r2.png", size = {16, 16},
  background = setmetatable({}, {__index = function() o:free(); collectgarbage(); return 1 end})})
try("object render ok", o.render, o, {path = out .. "/ok.png", size = {16, 16}})
-- 5. bytecode, and a chunk that returns a function built from bytecode
for _, mode in ipairs({"bt", "b"}) do
  local f, e = load(string.dump(function() return 1 end), "x", mode)
  print("load bytecode " .. mode, f and "ACCEPTED" or ("refused: " .. tostring(e)))
end
-- 6. a loop that never ends
print("alive")
while true do end
LUA
$HOVOX run --sandbox --output-dir out --max-time 3 attack.lua out; echo "rc=$?"
ls -A out outside
