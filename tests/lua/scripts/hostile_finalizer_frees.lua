-- Issue 32.1: every binding called while finalizers that free its objects (self and the objects
-- among its arguments) run during its allocations. The collector is set to step at every
-- allocation, so each finalizer runs inside some call; it frees through __close, which every
-- class has (so materials, features and sources too); an object freed while a binding uses it
-- must be destroyed only after the binding returns (or the binding says "object was freed"),
-- never used after its memory is gone (a crash here, a report under AddressSanitizer).
local out = arg[1]
local rounds = tonumber(arg[2] or "8")
local parts = {{mesh = hovox.generate.box{}, name = "a", material = "A"},
               {mesh = hovox.generate.sphere{radius = 4, segments = 8, rings = 6}, name = "b", material = "B"}}
local assembly = hovox.join_meshes(parts)
local function mesh() return hovox.join_meshes(parts) end
local function model() return hovox.voxelize(assembly, {dims = 8}) end
local function mats() return hovox.materials{{name = "A", color = "#ff0000", density = 1000}, "B"} end
local function object() return hovox.object(model()) end
local function source() return hovox.ags{feature = hovox.plane{normal = {0, 0, 1}}, d_grad = 4, ms = {1, 0}, me = {0, 1}} end
local function tray()
    local t = hovox.tray{dry_run = true}
    t:add{mesh = out .. "/part.stl", material = "VeroPureWhite"}
    return t
end
hovox.generate.box{}:save(out .. "/part.stl")

-- each case: the objects to free (made afresh every round), and the call
local cases = {
    {"Mesh.report", function() return {mesh()} end, function(m) return m:report() end},
    {"Mesh.count", function() return {mesh()} end, function(m) return m:count() end},
    {"Mesh.bodies", function() return {mesh()} end, function(m) return m:bodies() end},
    {"Mesh.materials", function() return {mesh()} end, function(m) return m:materials() end},
    {"Mesh.save", function() return {mesh()} end, function(m) return m:save(out .. "/m.obj") end},
    {"tostring(Mesh)", function() return {mesh()} end, function(m) return tostring(m) end},
    {"hovox.voxelize", function() return {mesh(), model()} end,
     function(m, like) return hovox.voxelize(m, {like = like}) end},
    {"hovox.contours", function() return {mesh()} end,
     function(m) return hovox.contours(m, {layer_height = 1}) end},
    {"hovox.facets", function() return {mesh()} end, function(m) return hovox.facets(m, {normal = {0, 0, 1}}) end},
    {"hovox.join_meshes", function() return {mesh(), mesh()} end,
     function(a, b) return hovox.join_meshes{{mesh = a, name = "x"}, {mesh = b, name = "y"}} end},
    {"Model.grids", function() return {model()} end, function(m) return m:grids() end},
    {"Model.voxels", function() return {model()} end, function(m) return m:voxels("occupancy") end},
    {"Model.transform", function() return {model()} end, function(m) return m:transform() end},
    {"Model.meta", function() return {model()} end, function(m) return m:meta("hovox.regions.json") end},
    {"Model.regions", function() return {model()} end, function(m) return m:regions() end},
    {"Model.save", function() return {model()} end, function(m) return m:save(out .. "/m.vdb") end},
    {"Model.add_grid", function() return {model()} end, function(m) return m:add_grid("g", function(x) return x end) end},
    {"Model.contour", function() return {model()} end, function(m) return m:contour() end},
    {"Model.mask", function() return {model()} end, function(m) return m:mask("occupancy") end},
    {"Model.harmonic", function() return {model(), mesh()} end,
     function(m, me) return m:harmonic(me, {normal = {0, 0, 1}}, {normal = {0, 0, -1}}) end},
    {"Model.render", function() return {model()} end,
     function(m) return m:render{path = out .. "/r.png", size = {16, 16}, surface = true} end},
    {"Model.export", function() return {model()} end, function(m) return m:export{path = out .. "/e.vti"} end},
    {"Model.layers", function() return {model(), mesh()} end,
     function(m, me) return m:layers{mesh = me, dir = out .. "/s", mode = "mask", layers = {0, 2}, force = true} end},
    {"tostring(Model)", function() return {model()} end, function(m) return tostring(m) end},
    {"hovox.object", function() return {model(), mats()} end, function(m, t) return hovox.object(m, t) end},
    {"Object.regions", function() return {object()} end, function(o) return o:regions() end},
    {"Object.voxels", function() return {object()} end, function(o) return o:voxels() end},
    {"Object.materials", function() return {object()} end, function(o) return o:materials() end},
    {"Object.add_ags", function() return {object(), source()} end, function(o, s) return o:add_ags(s) end},
    {"Object.move_ags", function() local o, s = object(), source() o:add_ags(s) return {o, s} end,
     function(o, s) return o:move_ags(s, 1) end},
    {"Object.delete_ags", function() local o, s = object(), source() o:add_ags(s) return {o, s} end,
     function(o, s) return o:delete_ags(s) end},
    {"Object.set_blend", function() return {object()} end, function(o) return o:set_blend("idw", 2) end},
    {"Object.set_base", function() return {object()} end, function(o) return o:set_base({0.5, 0.5}, "a") end},
    {"Object.union", function() return {object(), object()} end, function(a, b) return a:union(b) end},
    {"Object.evaluate", function() return {object()} end, function(o) return o:evaluate() end},
    {"Object.probe", function() return {object()} end, function(o) return o:probe{0, 0, 0} end},
    {"Materials.names", function() return {mats()} end, function(t) return t:names() end},
    {"Materials.color", function() return {mats()} end, function(t) return t:color("A") end},
    {"Materials.property", function() return {mats()} end, function(t) return t:property("A", "density") end},
    {"Feature.distance", function() return {hovox.plane{normal = {0, 0, 1}}} end, function(f) return f:distance{1, 2, 3} end},
    {"tostring(Feature)", function() return {hovox.axis{direction = {0, 0, 1}}} end, function(f) return tostring(f) end},
    {"Source.eval", function() return {source()} end, function(s) return s:eval(1) end},
    {"Source.moved", function() return {source()} end, function(s) return s:moved(2) end},
    {"hovox.ags", function() return {hovox.plane{normal = {0, 0, 1}}} end,
     function(f) return hovox.ags{feature = f, d_grad = 4, ms = {1, 0}, me = {0, 1}, f = function(d) return d / 4 end} end},
    {"Tray.add", function() return {tray()} end,
     function(t) return t:add{mesh = out .. "/part.stl", material = "VeroPureWhite"} end},
    {"Tray.arrange", function() return {tray()} end, function(t) return t:arrange{} end},
}

-- the bindings the attack crashed (SIGSEGV), and every other one a few times
local reported = {["Mesh.bodies"] = true, ["Model.transform"] = true, ["Model.grids"] = true, ["Object.regions"] = true}
local objs, armed = {}, false
local killer = {__gc = function()
    if not armed then return end
    for _, o in ipairs(objs) do
        do local gone <close> = o end -- __close frees an object of any class
    end
end}
hovox.set_threads(1)
collectgarbage("incremental", 0, 100, 0) -- a step at every allocation
local only = arg[3]
for _, c in ipairs(cases) do
    local name, make, call = c[1], c[2], c[3]
    if not only or name == only then
        for _ = 1, reported[name] and 20 * rounds or rounds do
            objs = make()
            for _ = 1, 200 do setmetatable({}, killer) end
            armed = true
            local ok, err = pcall(call, table.unpack(objs))
            armed = false
            if not ok and not tostring(err):find("was freed", 1, true) then error(name .. ": " .. tostring(err)) end
        end
        print(name, "no crash")
    end
end
