# hostile script against the bindings of issue 16 (join_meshes, mesh:bodies/materials, OBJ
# save, regions, per-region grading, 3MF export and load): metatables that free objects and collect
# garbage mid-call, paths swapped after the check, links out of the output dir, foreign files,
# and a never-ending loop under the sandbox's time limit
mkdir -p "$TMP/out" "$TMP/outside" && ln -s "$TMP/outside" "$TMP/out/escape" && cd "$TMP" || exit 1
cp "$OLDPWD/tests/data/good/core_in_shell.3mf" outside/a.3mf
cp "$OLDPWD/tests/cli/hostile_prelude.lua" attack.lua # out, try(): lines 1-5
cat >>attack.lua <<'LUA'
local a = hovox.generate.box{min = {0, 0, 0}, max = {10, 10, 10}}
local b = hovox.generate.box{min = {3, 3, 3}, max = {7, 7, 7}}
-- 1. a part with a metatable whose __index frees the mesh and collects garbage
local victim = hovox.generate.box{min = {0, 0, 0}, max = {1, 1, 1}}
try("part metatable", hovox.join_meshes, {setmetatable({}, {__index = function(t, k)
  victim:free(); collectgarbage(); return k == "mesh" and victim or "x" end})})
-- 2. the parts list itself with a metatable
try("parts metatable", hovox.join_meshes, setmetatable({}, {__index = function() return {mesh = a} end, __len = function() return 3 end}))
-- 3. a name whose __tostring frees the mesh: names must be strings
try("name object", hovox.join_meshes, {{mesh = a, name = setmetatable({}, {__tostring = function() a:free(); collectgarbage(); return "n" end})}})
-- 4. a mesh freed before the join
local gone = hovox.generate.box{min = {0, 0, 0}, max = {1, 1, 1}}
gone:free()
try("freed mesh", hovox.join_meshes, {{mesh = gone}})
local asm = hovox.join_meshes{{mesh = b, name = "core", material = "Agilus"}, {mesh = a, name = "shell", material = "Vero"}}
print("bodies", #asm:bodies(), "materials", #asm:materials())
-- 4b. the named copy of the methods in package.loaded (for error messages) changed: no object's
-- method changes, so the OBJ writes below are still checked (their messages lose the name)
package.loaded["hovox.Mesh"].save = function() return "tampered" end
-- 5. OBJ written through a link in the output dir, outside it, and with a swapped path
try("obj via link", asm.save, asm, out .. "/escape/x.obj")
try("obj outside", asm.save, asm, "/tmp/hx_outside.obj")
local swap = setmetatable({}, {__index = function() collectgarbage(); return true end})
try("obj options metatable", asm.save, asm, out .. "/ok.obj", swap)
-- 6. regions and per-region grading with hostile names
local m = hovox.voxelize(asm, {voxel_size = 0.5})
print("regions", #m:regions())
local obj = hovox.object(m)
local axis = hovox.axis{origin = {0, 0, 0}, direction = {0, 0, 1}}
local src = hovox.ags{feature = axis, d_grad = 2, ms = {1, 0}, me = {0, 1}}
try("region object", obj.add_ags, obj, src, setmetatable({}, {__tostring = function() obj:free(); return "core" end}))
try("unknown region", obj.add_ags, obj, src, "nope")
try("region while freed", function() local o = hovox.object(m); o:free(); o:add_ags(src, "core") end)
local g = obj:evaluate()
-- 7. 3MF export through a link, with options whose __index swaps the path after the check
try("3mf via link", g.export, g, {path = out .. "/escape/p.3mf"})
local n = 0
local sw = setmetatable({}, {__index = function(t, k)
  n = n + 1; collectgarbage()
  if k == "path" then return n == 1 and out .. "/fine.3mf" or "/tmp/hx_swapped.3mf" end
  return nil end})
try("3mf options metatable", g.export, g, sw)
try("3mf bits 12", g.export, g, {path = out .. "/b.3mf", bits = 12})
try("3mf ok", g.export, g, {path = out .. "/good.3mf", bits = 16, volumetric = true})
-- 8. reading a 3MF outside the output dir, and the one just written
try("load outside 3mf", hovox.load, "outside/a.3mf")
try("load_mesh outside 3mf", hovox.load_mesh, "outside/a.3mf")
try("load own 3mf", hovox.load, out .. "/good.3mf")
-- 9. a loop that never ends
print("alive")
while true do end
LUA
$HOVOX run --sandbox --output-dir out --max-time 2 attack.lua out; echo "rc=$?"
ls -A out outside; ls /tmp/hx_outside.obj /tmp/hx_swapped.3mf 2>&1 | sed "s|$TMP|\$TMP|"
