# scripts/bench/42-grade-contour.sh - issue 17: what grading from the model's contour costs a
# user over grading from an axis, end to end (`hovox grade` with its load and save), on the
# 200k-facet knot voxelized at 512, vs scipy.ndimage.distance_transform_edt on the same mask (the
# occupancy over the box the contour's EDT covers, bench_mask). Contour and axis runs alternate so
# both see the same machine load; the per-run differences' median is the figure. Goals: <= 0.03x
# scipy; the contour-graded file <= 1.5x the axis-graded one (same grids: the contour's field is
# recomputed on load, not stored; the rest of the gap is how well each grading's material
# fractions compress).
echo
echo "== grade: contour minus axis, 200k-facet knot at 512, vs scipy distance_transform_edt on the same mask (goals: <= 0.03x, file <= 1.5x)"
knot=$work/knot200k.stl
[ -f "$knot" ] || "$HOVOX" generate knot facets=200000 -o "$knot" >/dev/null
occ=$work/knot512.vdb
[ -f "$occ" ] || "$HOVOX" voxelize "$knot" --dims 512 -o "$occ" -q >/dev/null
drv=$BUILD/bench-tools/bench_mask
if [ ! -x "$drv" ]; then
    echo "skipped: $drv not built (make bench-tools)"
else
    g="--materials A,B,C --ms 1,0,0 --me 0,0.5,0.5 -q"
    contour() { wall "$HOVOX" grade "$occ" -o "$work/knot512_contour.vdb" --frf contour --ranges 0,4,0 $g; }
    axis() { wall "$HOVOX" grade "$occ" -o "$work/knot512_axis.vdb" --frf axis:0,0,0:0,0,1 --ranges 0,40,0 $g; }
    contour >/dev/null
    axis >/dev/null
    tc="" ta="" td=""
    i=0
    while [ $i -lt "$runs" ]; do
        c=$(contour)
        a=$(axis)
        tc="$tc $c" ta="$ta $a" td="$td $(awk -v c="$c" -v a="$a" 'BEGIN { printf "%.4f", c - a }')"
        i=$((i + 1))
    done
    # shellcheck disable=SC2086
    t_c=$(median_of $tc) t_a=$(median_of $ta) t_d=$(median_of $td) s_d=$(spread_of $td)
    mask=$work/knot512_mask.raw
    dims=$("$drv" "$occ" occupancy "$mask")
    /usr/bin/python3 "$here/bench/edt_scipy.py" time "$mask" "$dims" --runs "$runs" >"$work/grade_scipy.txt"
    t_s=$(awk '/^scipy/ {print $3}' "$work/grade_scipy.txt")
    s_s=$(awk '/^scipy/ {printf "%.3f-%.3f", $6, $8}' "$work/grade_scipy.txt")
    printf "contour - axis  hovox %7.3f s (runs %s; contour %.3f s, axis %.3f s)   scipy %7.3f s (%s, mask %s)   ratio %sx\n" \
        "$t_d" "$s_d" "$t_c" "$t_a" "$t_s" "$s_s" "$dims" "$(ratio "$t_d" "$t_s")"
    b_c=$(stat -c %s "$work/knot512_contour.vdb") b_a=$(stat -c %s "$work/knot512_axis.vdb")
    printf "files           contour %6.1f MB   axis %6.1f MB   ratio %sx\n" \
        "$(awk -v b="$b_c" 'BEGIN { print b / 1e6 }')" "$(awk -v b="$b_a" 'BEGIN { print b / 1e6 }')" "$(ratio "$b_c" "$b_a")"
    echo "(contour --ranges 0,4,0, axis z --ranges 0,40,0, both Ms 1,0,0 Me 0,0.5,0.5; scipy single-threaded)"
    rm -f "$mask"
fi
