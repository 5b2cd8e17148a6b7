# a graded model to .vti, read back by VTK: geometry, arrays, values at two voxels
/usr/bin/python3 tests/cli/cases/export_model.py "$TMP/m.vdb" || exit 9
out=$($HOVOX export "$TMP/m.vdb" -o "$TMP/m.vti"); rc=$?
printf "%s\n" "$out" | sed -E "s/\([0-9]+ bytes\)/(N bytes)/"
[ $rc = 0 ] || exit $rc
# point 7 = voxel (7, 0, 0): b = 7/11; point 41 = voxel (5, 3, 0): in the hole
/usr/bin/python3 tests/cli/cases/export_readback.py "$TMP/m.vti" 7 41
