# hostile script against the C volume store and the native .vdb reader of stop 25 (what a script
# reaches through models): add_grid functions that free the model, collect garbage, add grids to
# the same model or save and reload it while C walks its leaves; saves through a link out of the
# output dir and onto the model's own file; loads of a model while another holds its leaves;
# render and object options whose __index frees the model or swaps the path after its check;
# bytecode, and a loop that never ends
mkdir -p "$TMP/out" "$TMP/outside" && ln -s "$TMP/outside" "$TMP/out/escape" && cd "$TMP" || exit 1
cp "$OLDPWD/tests/cli/hostile_prelude.lua" attack.lua # out, try(): lines 1-5
cat >>attack.lua <<'LUA'
local box = hovox.generate.box{min = {0, 0, 0}, max = {10, 10, 10}}
local model = hovox.voxelize(box, {voxel_size = 1})
-- 1. add_grid: a function that frees the model midway, one that adds a grid to the same model
-- (the store's grid table grows under the call), one that saves and reloads it, one that
-- collects garbage with the model unreachable but for the call
local victim = hovox.voxelize(box, {voxel_size = 1})
local calls = 0
try("add_grid frees", victim.add_grid, victim, "g", function(x, y, z)
  calls = calls + 1; if calls == 100 then victim:free(); collectgarbage() end; return x end)
print("victim freed", pcall(victim.grids, victim) and "no" or "yes")
local k = 0
try("add_grid adds", model.add_grid, model, "outer", function(x, y, z)
  k = k + 1; if k == 50 then model:add_grid("inner", function() return 1 end) end; return y end)
local names = {}
for _, g in ipairs(model:grids()) do names[#names + 1] = g.name end
print("grids", table.concat(names, ","))
local c3 = 0
try("add_grid saves", model.add_grid, model, "saved", function(x, y, z)
  c3 = c3 + 1
  if c3 == 10 then model:save(out .. "/mid.vdb"); local r = hovox.load(out .. "/mid.vdb"); print("mid grids", #r:grids()); r:free() end
  return z end)
try("add_grid NaN", model.add_grid, model, "nan", function() return 0 / 0 end)
try("add_grid name used", model.add_grid, model, "outer", function() return 1 end)
do
  local tmp = hovox.voxelize(box, {voxel_size = 2})
  try("add_grid collects", tmp.add_grid, tmp, "c", function() collectgarbage(); return 1 end)
end
collectgarbage()
-- 2. saves: through the link, onto a path given as a table, onto the file the model came from
try("save through link", model.save, model, out .. "/escape/m.vdb")
try("save table path", model.save, model, setmetatable({}, {__tostring = function() return out .. "/t.vdb" end}))
try("save ok", model.save, model, out .. "/m.vdb")
local loaded = hovox.load(out .. "/m.vdb")
try("save onto own file", loaded.save, loaded, out .. "/m.vdb")
local again = hovox.load(out .. "/m.vdb")
print("reloaded voxels", again:voxels(), loaded:voxels(), model:voxels())
try("load a directory", hovox.load, out)
try("load missing", hovox.load, out .. "/none.vdb")
try("load the link's target", hovox.load, out .. "/escape")
-- 3. render options: __index that frees the model, collects garbage, swaps the path after it
-- was checked; a clip table whose __index frees the model
local r1 = hovox.load(out .. "/m.vdb")
try("render frees", r1.render, r1, setmetatable({path = out .. "/r1.png"}, {__index = function(t, key)
  r1:free(); collectgarbage(); return nil end}))
print("r1 freed", pcall(r1.grids, r1) and "no" or "yes")
local n = 0
try("render swapped path", again.render, again, setmetatable({size = {16, 16}}, {__index = function(t, key)
  if key == "path" then n = n + 1; return n < 2 and out .. "/r2.png" or out .. "/escape/r2.png" end end}))
try("render clip frees", again.render, again, {path = out .. "/r3.png", size = {16, 16},
  clip = setmetatable({}, {__index = function() again:free(); collectgarbage(); return nil end})})
-- 4. an object over a model freed from its options
local mats = hovox.materials{"A", "B"}
local m4 = hovox.voxelize(box, {voxel_size = 1})
try("object options free", hovox.object, m4, mats, setmetatable({}, {__index = function() m4:free(); collectgarbage(); return nil end}))
local o = hovox.object(m4, mats)
o:add_ags(hovox.ags{feature = hovox.axis{origin = {0, 0, 0}, direction = {0, 0, 1}}, d_grad = 10, ms = {1, 0}, me = {0, 1}})
m4:free(); collectgarbage() -- the object holds its own reference
try("evaluate after the model's free", o.evaluate, o)
try("evaluate options free", o.evaluate, o, setmetatable({}, {__index = function() o:free(); collectgarbage(); return nil end}))
try("object save through link", o.save, o, out .. "/escape/o.vdb")
try("object save", o.save, o, out .. "/o.vdb")
try("render ok", model.render, model, {path = out .. "/ok.png", size = {16, 16}})
-- 5. bytecode
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
