$HOVOX voxelize "$SHARED/meshes/bunny_1500.stl" --dims 4096 --max-memory 1G -o "$TMP/b.vdb"; echo "rc=$?"; ls "$TMP"
$HOVOX voxelize "$SHARED/meshes/bunny_1500.stl" --dims 128 --max-memory 1M -o "$TMP/b.vdb"; echo "rc=$?; files: $(ls "$TMP" | wc -l)"
