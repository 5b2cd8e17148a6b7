# camera options: --up only with --eye; an eye straight above the model with the default up
# looks down with +y up on the screen (as the top view) instead of failing
$HOVOX generate box sx=4 sy=4 sz=4 -o "$TMP/b.stl" >/dev/null
$HOVOX voxelize "$TMP/b.stl" -o "$TMP/b.vdb" --dims 8 >/dev/null
$HOVOX render "$TMP/b.vdb" -o "$TMP/t.png" --view top --up 0,1,0
echo "rc=$?"
$HOVOX render "$TMP/b.vdb" -o "$TMP/d.png" --eye 2,2,50 --size 16x16
echo "rc=$?"
