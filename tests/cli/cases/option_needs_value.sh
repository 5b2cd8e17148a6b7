# an option given without its value says so (exit 2), in every command
for cmd in voxelize grade export generate contours layers render profile; do
    $HOVOX $cmd x -o
done
$HOVOX voxelize x.stl --dims
echo "rc=$?"
