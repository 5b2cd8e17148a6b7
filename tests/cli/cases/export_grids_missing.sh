# export --grids names float grids of the model; one it does not have is bad input (exit 1),
# the message lists the float grids there are, and nothing is written
$HOVOX generate box sx=6 sy=4 sz=4 -o "$TMP/b.stl" >/dev/null
$HOVOX voxelize "$TMP/b.stl" -o "$TMP/b.vdb" --voxel-size 1 >/dev/null
$HOVOX export "$TMP/b.vdb" -o "$TMP/bad.vti" --grids sigma
echo "rc=$?"
ls "$TMP" | grep -c '^bad'
