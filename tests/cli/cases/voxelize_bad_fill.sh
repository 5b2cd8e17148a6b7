$HOVOX voxelize "$SHARED/meshes/bunny_1500.stl" --fill magic -o "$TMP/b.vdb"
