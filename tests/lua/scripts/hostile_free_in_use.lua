-- Issue 19, findings 1 and 4: option tables with a metatable are refused (no script code runs
-- while C reads options, so a path cannot change between its check and its use), and an object
-- freed while a call would use it raises a Lua error instead of crashing.
local out = arg[1]
local mesh = hovox.generate.box{}
local m = hovox.voxelize(mesh, {dims = 16})
local mats = hovox.materials{"A", "B"}
-- 1. an __index table that hands out a different path on every read
local n = 0
local evil = setmetatable({}, {__index = function(_, k)
    n = n + 1
    if k == "path" then return n == 1 and out .. "/x.png" or "/tmp/hovox-escape.png" end
end})
print("metatable options:", pcall(m.render, m, evil))
print("metamethod calls:", n)
-- 4a. the grading callback frees the object it is being added to
local o = hovox.object(m, mats)
print("free in f:", pcall(o.add_ags, o, {feature = hovox.point{0, 0, 0}, d_grad = 2, ms = {1, 0}, me = {0, 1},
                                          f = function(d) o:free() return d / 2 end}))
-- 4b. finalizers that free the model may run while the options are read
local victim = hovox.voxelize(mesh, {dims = 8})
for _ = 1, 2000 do setmetatable({}, {__gc = function() victim:free() end}) end
local ok, err = pcall(victim.render, victim, {path = out .. "/v.png", size = {16, 16}, background = "#000000"})
print("finalizer free: no crash,", ok or tostring(err):find("object was freed", 1, true) ~= nil)
-- 4c. a freed mesh given as an option
local gone = hovox.generate.box{}
gone:free()
print("freed mesh:", pcall(m.layers, m, {mesh = gone, dir = out .. "/s", mode = "mask"}))
