$HOVOX voxelize "$SHARED/meshes/bunny_1500.stl" --iso 0 -o "$TMP/x.vdb"; rc=$?; ls "$TMP"; exit $rc
