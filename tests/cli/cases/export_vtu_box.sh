# one hexahedron per voxel inside a box: voxels 9..11 x 0..5 x 0..3 (x >= 4.4 mm)
/usr/bin/python3 tests/cli/cases/export_model.py "$TMP/m.vdb" || exit 9
out=$($HOVOX export "$TMP/m.vdb" -o "$TMP/m.vtu" --box 4.4,-1,-1,10,10,10 --properties none); rc=$?
printf "%s\n" "$out" | sed -E "s/\([0-9]+ bytes\)/(N bytes)/"
[ $rc = 0 ] || exit $rc
/usr/bin/python3 tests/cli/cases/export_readback.py "$TMP/m.vtu" 0
