# an assembly read from OBJ (an Agilus core in a Vero shell): one region per body, the first in
# file order keeping the voxels where they overlap, the overlap reported; --json too; then the
# shell first (the core keeps nothing); the plan of --dry-run names the bodies
$HOVOX run tests/lua/scripts/assembly.lua "$TMP" &&
$HOVOX voxelize "$TMP/assembly.obj" -o "$TMP/a.vdb" --voxel-size 0.5 -q &&
$HOVOX voxelize "$TMP/assembly.obj" -o "$TMP/a.vdb" --voxel-size 0.5 -q --json &&
$HOVOX voxelize "$TMP/assembly.obj" --voxel-size 0.5 --dry-run &&
$HOVOX run tests/lua/scripts/assembly.lua "$TMP" shell-first &&
$HOVOX voxelize "$TMP/assembly.obj" -o "$TMP/b.vdb" --voxel-size 0.5 -q
echo "rc=$?"
