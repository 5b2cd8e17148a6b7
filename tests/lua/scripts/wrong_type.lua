local model = hovox.voxelize("box.stl", {dims = 8})
