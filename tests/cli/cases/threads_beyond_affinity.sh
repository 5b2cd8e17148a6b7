# issue 32 item 22: more threads than the processors this process may run on (its affinity
# mask: taskset here, mpirun's binding on a cluster) is a warning; the default follows the mask
"$HOVOX" generate box size=4,4,2 -o "$TMP/b.stl" >/dev/null
taskset -c 0 "$HOVOX" voxelize "$TMP/b.stl" --voxel-size 1 -o "$TMP/b.vdb" --threads 2 -q >/dev/null
echo "rc $?"
taskset -c 0 "$HOVOX" voxelize "$TMP/b.stl" --voxel-size 1 -o "$TMP/c.vdb" -q >/dev/null
echo "rc $?"
