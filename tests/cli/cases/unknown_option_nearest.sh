# an unknown long option that is a typo of one the command takes names it (at most 2 edits, fewer
# than half its letters); the common options only where the command takes them; else no guess
cd "$TMP"
"$HOVOX" generate box max=2,2,2 -o b.stl >/dev/null
"$HOVOX" voxelize b.stl -o x.vdb --voxelsize 1; echo "rc=$?"
"$HOVOX" voxelize b.stl -o x.vdb --thread 2; echo "rc=$?"
"$HOVOX" info b.stl --thread 2; echo "rc=$?"
"$HOVOX" voxelize b.stl -o x.vdb --bogus; echo "rc=$?"
