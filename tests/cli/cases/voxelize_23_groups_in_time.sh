# issue 32 item 20: a multi-body OBJ voxelizes about as fast as the same mesh as one body. The
# 200,000-facet knot as 23 groups of consecutive facets (an exporter's faces: 23 open bodies) took
# 46 s at 256 voxels against 1.3 s as one body (the winding number of every undecided centre over
# its open body's facets, a fork and join per body and loop); now about 1.4 s. The timeout (30 s,
# ample for the loaded 2 cores and sanitizers) catches a return of the old rule; both models'
# occupied voxels are pinned (the open groups vote, the closed body floods).
cd "$TMP" || exit 1
$HOVOX generate knot facets=200000 -o knot.stl >/dev/null
/usr/bin/python3 "$OLDPWD/scripts/bench/split_obj.py" knot.stl 23 one.obj groups.obj
timeout 30 $HOVOX voxelize groups.obj --dims 256 -o groups.vdb >groups.txt; echo "rc=$?"
grep -E "^(mesh|occupied)" groups.txt
$HOVOX voxelize one.obj --dims 256 -o one.vdb >one.txt; echo "rc=$?"
grep -E "^(mesh|occupied)" one.txt
