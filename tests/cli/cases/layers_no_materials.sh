$HOVOX generate box sx=4 sy=4 sz=4 -o "$TMP/b.stl" &&
$HOVOX voxelize "$TMP/b.stl" --voxel-size 0.5 -o "$TMP/b.vdb" &&
$HOVOX layers "$TMP/b.vdb" --mesh "$TMP/b.stl" -o "$TMP/stack" --dpi 50,50 --layer-height 1
echo "rc=$?"; ls "$TMP"
