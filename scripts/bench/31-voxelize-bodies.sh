# scripts/bench/31-voxelize-bodies.sh - issue 32 item 20: the 200,000-facet knot as one OBJ body
# (the anchor) and as 23 groups of consecutive facets (an exporter's faces: 23 open bodies), and
# 23 closed spheres' worth of small bodies; voxelize at 256. Goal: 23 groups <= 1.5x one body.
echo
echo "== voxelize an assembly: the knot as 23 OBJ groups vs one body, 256 voxels (goal <= 1.5x)"
knot=$work/knot200k.stl
[ -f "$knot" ] || "$HOVOX" generate knot facets=200000 -o "$knot"
[ -f "$work/knot_23.obj" ] || /usr/bin/python3 "$here/bench/split_obj.py" "$knot" 23 "$work/knot_one.obj" "$work/knot_23.obj"
t_one=$(median vox_knot_one "$HOVOX" voxelize "$work/knot_one.obj" --dims 256 -o "$work/knot_one.vdb" -q)
t_23=$(median vox_knot_23 "$HOVOX" voxelize "$work/knot_23.obj" --dims 256 -o "$work/knot_23.vdb" -q)
printf "one body %7.3f s (%6.1f MiB)   23 groups %7.3f s (%6.1f MiB)   ratio %sx\n" \
    "$t_one" "$(peak_rss "$HOVOX" voxelize "$work/knot_one.obj" --dims 256 -o "$work/knot_one.vdb" -q)" \
    "$t_23" "$(peak_rss "$HOVOX" voxelize "$work/knot_23.obj" --dims 256 -o "$work/knot_23.vdb" -q)" \
    "$(ratio "$t_23" "$t_one")"
echo "(the groups are open: each body's centres by the vote, the lines' majority where it ties)"
