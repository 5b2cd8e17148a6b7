$HOVOX voxelize "$SHARED/meshes/bunny_1500.stl" --dims 256 --dry-run
