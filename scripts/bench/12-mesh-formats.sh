# scripts/bench/12-mesh-formats.sh - issue 16: `hovox info` end to end on the same
# 1,000,000-facet mesh as binary STL (the anchor), OBJ, binary PLY and 3MF (written by lib3mf).
# Goal: OBJ and PLY within 2x of the STL reader; 3MF (hovox's own streamed reader) within 1.5x (issue 26).
echo
echo "== mesh formats: info on the same 1,000,000-facet knot (anchor: binary STL; goal OBJ, PLY <= 2x, 3MF <= 1.5x)"
mesh=$work/knot1m.stl
[ -f "$mesh" ] || "$HOVOX" generate knot facets=1000000 -o "$mesh"
[ -f "$work/knot1m.3mf" ] || "$BUILD/bench-tools/bench_mesh_formats" "$mesh" "$work/knot1m"
t_stl=$(median fmt_stl "$HOVOX" info "$mesh")
printf "%-12s %7.3f s   %6.1f MiB peak   %s\n" "binary STL" "$t_stl" "$(peak_rss "$HOVOX" info "$mesh")" \
    "$(du -h "$mesh" | cut -f1)"
for ext in obj ply 3mf; do
    f=$work/knot1m.$ext
    t=$(median "fmt_$ext" "$HOVOX" info "$f")
    printf "%-12s %7.3f s   %6.1f MiB peak   %s   %sx STL\n" "$ext" "$t" "$(peak_rss "$HOVOX" info "$f")" \
        "$(du -h "$f" | cut -f1)" "$(ratio "$t" "$t_stl")"
done
echo "(3MF: lib3mf writes six decimals, so a few vertices may weld differently; the facets are the same)"
