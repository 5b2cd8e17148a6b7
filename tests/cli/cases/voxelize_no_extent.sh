# issue 32 item 12: a mesh that is one point (every vertex the same) has no extent: refused at every
# resolution (before, --voxel-size made an 8-voxel model of it). A flat mesh is still a surface.
printf 'v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n' >"$TMP/point.obj"
for res in "--voxel-size 1" "--dims 10" "--voxel-size 0.1,0.2,0.3"; do
    $HOVOX voxelize "$TMP/point.obj" $res -o "$TMP/p.vdb" -q; echo "rc=$?"
done
ls "$TMP"
