# the render succeeds, the output cannot be written: exit 4 and no file anywhere
$HOVOX generate sphere -o "$TMP/s.stl" >/dev/null && $HOVOX voxelize "$TMP/s.stl" --dims 16 -o "$TMP/s.vdb" -q >/dev/null
$HOVOX render "$TMP/s.vdb" --size 16x16 -o "$TMP/missing-dir/out.png" -q; echo "rc=$?"; ls "$TMP"
