$HOVOX voxelize "$SHARED/meshes/bunny_1500.stl" --dims 0 -o "$TMP/b.vdb"
