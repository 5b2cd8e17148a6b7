# A feature given too few values names the missing value in the --frf syntax (issue 32 item 19:
# `--frf axis:0,0,0` named a --direction option that does not exist).
cd "$TMP"
"$HOVOX" generate box max=20,10,2 -o b.stl >/dev/null
"$HOVOX" voxelize b.stl --voxel-size 0.5 -o o.vdb -q >/dev/null
for f in axis:0,0,0 axis plane:1,2,3 segment:1,1,1 halfspace field:x.vti point; do
    "$HOVOX" grade o.vdb -o g.vdb --materials A,B --frf $f --ranges 0,10,0 --ms 1,0 --me 0,1; echo "rc=$?"
done
ls
