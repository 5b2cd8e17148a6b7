# a plain voxelized model: occupancy only, with a note
$HOVOX generate box sx=4 sy=3 sz=2 -o "$TMP/b.stl" >/dev/null && $HOVOX voxelize "$TMP/b.stl" --voxel-size 1 -o "$TMP/b.vdb" -q >/dev/null || exit 9
out=$($HOVOX export "$TMP/b.vdb" -o "$TMP/b.vti"); rc=$?
printf "%s\n" "$out" | sed -E "s/\([0-9]+ bytes\)/(N bytes)/"
[ $rc = 0 ] || exit $rc
/usr/bin/python3 tests/cli/cases/export_readback.py "$TMP/b.vti"
