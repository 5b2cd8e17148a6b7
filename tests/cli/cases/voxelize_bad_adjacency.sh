$HOVOX voxelize "$SHARED/meshes/bunny_1500.stl" --adjacency 18 -o "$TMP/b.vdb"
