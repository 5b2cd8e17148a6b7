$HOVOX voxelize "$SHARED/meshes/bunny_1500.stl"
