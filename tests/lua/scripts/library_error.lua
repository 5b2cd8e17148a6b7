print("loading")
local mesh = hovox.load_mesh("no/such/mesh.stl")
