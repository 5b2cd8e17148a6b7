-- tests/lua/scripts/assembly.lua - an assembly for the CLI tests while no multi-body mesh reader
-- exists: an Agilus core (4 mm cube) inside a Vero shell (10 mm cube), the core first, written as
-- OBJ (bodies kept), STL (geometry only) and voxelized at 0.5 mm into OUT/assembly.vdb; with
-- "shell-first", the shell comes first and takes every voxel of the core.
local out, order = arg[1], arg[2]
local outer = hovox.generate.box{min = {0, 0, 0}, max = {10, 10, 10}}
local inner = hovox.generate.box{min = {3, 3, 3}, max = {7, 7, 7}}
local core, shell = {mesh = inner, name = "core", material = "Agilus"}, {mesh = outer, name = "shell", material = "Vero"}
local a = hovox.join_meshes(order == "shell-first" and {shell, core} or {core, shell})
a:save(out .. "/assembly.obj")
a:save(out .. "/assembly.stl")
hovox.voxelize(a, {voxel_size = 0.5}):save(out .. "/assembly.vdb")
