# .vtu with 2x2x2 blocks kept when any voxel is occupied; block (2,1,0), cell 14,
# holds 4 hole voxels: occupancy 0.5, b averaged over voxels i = 4 only (4/11)
/usr/bin/python3 tests/cli/cases/export_model.py "$TMP/m.vdb" || exit 9
out=$($HOVOX export "$TMP/m.vdb" -o "$TMP/m.vtu" --coarsen 2 --keep any --properties voigt); rc=$?
printf "%s\n" "$out" | sed -E "s/\([0-9]+ bytes\)/(N bytes)/"
[ $rc = 0 ] || exit $rc
/usr/bin/python3 tests/cli/cases/export_readback.py "$TMP/m.vtu" 0 14
