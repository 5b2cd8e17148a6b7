# issue 27 item 2: bodies get materials from the command line (--material BODY=MATERIAL), whatever
# the file says; grade then builds its table from them. A body that is not there is named with the
# bodies there are (exit 1); a value without '=' is a usage error (exit 2).
cat >"$TMP/two.obj" <<'OBJ'
v 0 0 0
v 4 0 0
v 0 4 0
v 0 0 4
v 10 0 0
v 14 0 0
v 10 4 0
v 10 0 4
o left
f 1 3 2
f 1 2 4
f 1 4 3
f 2 3 4
o right
usemtl Vero
f 5 7 6
f 5 6 8
f 5 8 7
f 6 7 8
OBJ
$HOVOX voxelize "$TMP/two.obj" --material left=Agilus --material right=Tango --voxel-size 0.5 -o "$TMP/a.vdb" | grep region
$HOVOX grade "$TMP/a.vdb" -o "$TMP/g.vdb" | grep -E "^(region|graded)"
$HOVOX voxelize "$TMP/two.obj" --material middle=Agilus --voxel-size 0.5 -o "$TMP/b.vdb"; echo "rc $?"
$HOVOX voxelize "$TMP/two.obj" --material left --voxel-size 0.5 -o "$TMP/b.vdb"; echo "rc $?"
ls "$TMP"
