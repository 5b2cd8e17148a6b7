-- a halftoned stack from a sandboxed script (needs the blue-noise tile)
local out = arg[1]
local mesh = hovox.generate.box{max = {4, 4, 0.2}}
local o = hovox.object(hovox.voxelize(mesh, {voxel_size = 0.5}), hovox.materials{"A", "B"})
o:add_ags{feature = hovox.plane{normal = {1, 0, 0}}, d_grad = 4, ms = {1, 0}, me = {0, 1}}
local r = o:evaluate():layers{mesh = mesh, dir = out .. "/stack", dpi = {100, 100}, layer_height = 0.1}
print("layers:", r.layers)
