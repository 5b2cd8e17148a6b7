$HOVOX generate box sx=4 sy=4 sz=4 -o "$TMP/b.stl" &&
$HOVOX generate sphere radius=3 cx=40 -o "$TMP/far.stl" &&
$HOVOX voxelize "$TMP/b.stl" --voxel-size 0.5 -o "$TMP/b.vdb" &&
$HOVOX grade "$TMP/b.vdb" -o "$TMP/g.vdb" --materials A,B --frf point:0,0,0 --ranges 0,4,0 --ms 1,0 --me 0,1 -q &&
$HOVOX layers "$TMP/g.vdb" --mesh "$TMP/far.stl" -o "$TMP/stack" --dpi 50,50 --layer-height 1
echo "rc=$?"; ls "$TMP"
