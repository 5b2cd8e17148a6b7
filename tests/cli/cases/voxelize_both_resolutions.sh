$HOVOX voxelize "$SHARED/meshes/bunny_1500.stl" --dims 10 --voxel-size 0.1 -o "$TMP/b.vdb"
