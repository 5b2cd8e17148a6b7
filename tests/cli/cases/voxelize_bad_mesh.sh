$HOVOX voxelize tests/data/bad/binary_nan.stl -o "$TMP/b.vdb"; echo "rc=$?"; ls "$TMP"
