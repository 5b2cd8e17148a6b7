$HOVOX voxelize "$SHARED/meshes/bunny_1500.stl" --dims 16 -o /nonexistent-dir/b.vdb -q
