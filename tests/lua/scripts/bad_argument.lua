local model = hovox.voxelize(hovox.generate.box{}, {dims = 8})
local obj = hovox.object(model, hovox.materials{"A", "B"})
obj:add_ags{feature = hovox.point{0, 0, 0}, d_grad = -1, ms = {1, 0}, me = {0, 1}}
