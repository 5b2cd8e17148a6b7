# scripts/bench/12-mesh-formats.sh - issue 16: `hovox info` end to end on the same
# 1,000,000-facet mesh as binary STL (the anchor), OBJ, binary PLY and 3MF (written by lib3mf).
# Goal: OBJ and PLY within 2x of the STL reader; 3MF (hovox's own reader, its bulk elements read in pieces on
# the threads) within 1.5x (issue 26).
# The formats' runs are interleaved (STL, OBJ, PLY, 3MF, STL, ...), so each ratio compares runs
# that saw the same load on the machine; the ratio is of the medians, with the spread of the runs.
echo
echo "== mesh formats: info on the same 1,000,000-facet knot (anchor: binary STL; goal OBJ, PLY <= 2x, 3MF <= 1.5x)"
mesh=$work/knot1m.stl
[ -f "$mesh" ] || "$HOVOX" generate knot facets=1000000 -o "$mesh"
[ -f "$work/knot1m.3mf" ] || "$BUILD/bench-tools/bench_mesh_formats" "$mesh" "$work/knot1m"
for ext in stl obj ply 3mf; do "$HOVOX" info "$work/knot1m.$ext" >/dev/null; done # warm the page cache
t_stl="" t_obj="" t_ply="" t_3mf=""
i=0
while [ $i -lt "$runs" ]; do
    t_stl="$t_stl $(wall "$HOVOX" info "$mesh")"
    t_obj="$t_obj $(wall "$HOVOX" info "$work/knot1m.obj")"
    t_ply="$t_ply $(wall "$HOVOX" info "$work/knot1m.ply")"
    t_3mf="$t_3mf $(wall "$HOVOX" info "$work/knot1m.3mf")"
    i=$((i + 1))
done
# shellcheck disable=SC2086
m_stl=$(median_of $t_stl)
printf "%-12s %7.3f s   %6.1f MiB peak   %s   (runs %s)\n" "binary STL" "$m_stl" "$(peak_rss "$HOVOX" info "$mesh")" \
    "$(du -h "$mesh" | cut -f1)" "$(eval spread_of \$t_stl)"
for ext in obj ply 3mf; do
    f=$work/knot1m.$ext
    eval "ts=\$t_$ext"
    # shellcheck disable=SC2086
    t=$(median_of $ts)
    # shellcheck disable=SC2086
    printf "%-12s %7.3f s   %6.1f MiB peak   %s   %sx STL   (runs %s)\n" "$ext" "$t" "$(peak_rss "$HOVOX" info "$f")" \
        "$(du -h "$f" | cut -f1)" "$(ratio "$t" "$m_stl")" "$(spread_of $ts)"
done
echo "(3MF: lib3mf writes six decimals, so a few vertices may weld differently; the facets are the same)"
echo "(wall time on the threads hovox uses here: $(nproc); a 3MF's <vertices> and <triangles> are read in pieces, one a thread: BENCH_ONLY=3mf-one-core gives one core)"
