-- tests/lua/scripts/hostile_round3_bindings.lua - this round's Lua bindings (mesh:transform, mesh:set_material,
-- model:layers without a mesh) attacked as a hostile script would: option tables with metatables,
-- objects freed by finalizers mid-call, absurd placements, paths outside and through symlinks,
-- bytecode; tests/cli/cases/hostile_33_round3_bindings.sh runs it and a loop under --max-time
local out = arg[1]
local function try(name, fn, ...)
  local ok, err = pcall(fn, ...)
  print(name, ok and "ACCEPTED" or ("refused: " .. tostring(err):gsub("\n", " ")))
end
local box = hovox.generate.box{min = {0, 0, 0}, max = {4, 4, 2}}
-- 1. an option table with a metatable whose __index frees the mesh mid-call
try("transform, __index frees", function()
  local m = hovox.generate.box{min = {0, 0, 0}, max = {4, 4, 2}}
  local t = setmetatable({}, {__index = function(_, k) m:free(); collectgarbage(); return nil end})
  return m:transform(t)
end)
-- 2. a finalizer frees the mesh while the options are read (plain table, __gc on a junk object)
try("transform, finalizer frees", function()
  local m = hovox.generate.box{min = {0, 0, 0}, max = {4, 4, 2}}
  setmetatable({}, {__gc = function() m:free() end})
  collectgarbage()
  return m:transform{unit = "cm", rotate = {"x:90", "30@1,1,0"}, translate = {1, 2, 3}}
end)
-- 3. absurd placements
try("transform, zero scale", function() return box:transform{scale = 0} end)
try("transform, nan rotate", function() return box:transform{rotate = "x:nan"} end)
try("transform, zero axis", function() return box:transform{rotate = "30@0,0,0"} end)
try("transform, 10000 rotations", function() local r = {} for i = 1, 10000 do r[i] = "x:1" end return box:transform{rotate = r} end)
try("transform, huge scale", function() return box:transform{scale = 1e300} end)
try("transform, unknown unit", function() return box:transform{unit = "furlong"} end)
-- 4. set_material on a freed mesh, with a non-string, with a huge name
try("set_material freed", function() local m = hovox.generate.box{}; m:free(); return m:set_material("body 1", "A") end)
try("set_material table", function() return box:set_material({}, "A") end)
try("set_material unknown body", function() return box:set_material("nobody", "A") end)
try("set_material long name", function() return box:set_material(box:bodies()[1].name, string.rep("A", 1 << 20)) end)
-- 5. model:layers without a mesh; the model freed by a finalizer while options are read
local v = hovox.voxelize(box, {voxel_size = 1})
try("layers no mesh, model freed", function()
  local w = hovox.voxelize(box, {voxel_size = 1})
  setmetatable({}, {__gc = function() w:free() end})
  collectgarbage()
  return w:layers{dir = out .. "/l1", mode = "mask", dpi = {100, 100}, layer_height = 0.5}
end)
try("layers options with metatable", function()
  return v:layers(setmetatable({dir = out .. "/l2", mode = "mask"}, {__index = function() v:free() end}))
end)
try("layers dir outside", function() return v:layers{dir = "/tmp/hovox-escape-stack", mode = "mask"} end)
try("layers dir trailing", function() return v:layers{dir = out .. "/", mode = "mask"} end)
try("layers through a symlink", function() return v:layers{dir = out .. "/link/s", mode = "mask", dpi = {100, 100}, layer_height = 0.5} end)
try("layers onto the symlink", function() return v:layers{dir = out .. "/link", mode = "mask", dpi = {100, 100}, layer_height = 0.5, force = true} end)
try("save mesh through symlink", function() return box:transform{unit = "cm"}:save(out .. "/link/m.stl") end)
try("bytecode", function() assert(load(string.dump(function() return 1 end))) end)
