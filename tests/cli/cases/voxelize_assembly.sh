# an assembly read from OBJ (an Agilus core in a solid Vero box): one region per body, a voxel to
# the body holding its centre (the core its 8^3 = 512), the first in file order keeping the
# voxels whose centres both hold (the overlap, 512), the outward surface voxels of the core to the
# shell; --json too; then the shell first (the core keeps nothing, still an overlap of 512); the
# plan of --dry-run names the bodies
$HOVOX run tests/lua/scripts/assembly.lua "$TMP" &&
$HOVOX voxelize "$TMP/assembly.obj" -o "$TMP/a.vdb" --voxel-size 0.5 &&
$HOVOX voxelize "$TMP/assembly.obj" -o "$TMP/a.vdb" --voxel-size 0.5 --json &&
$HOVOX voxelize "$TMP/assembly.obj" --voxel-size 0.5 --dry-run &&
$HOVOX run tests/lua/scripts/assembly.lua "$TMP" shell-first &&
$HOVOX voxelize "$TMP/assembly.obj" -o "$TMP/b.vdb" --voxel-size 0.5
echo "rc=$?"
