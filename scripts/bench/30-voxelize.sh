# scripts/bench/30-voxelize.sh - issue 3: voxelize a 200,000-facet closed mesh (tube around
# a torus knot), surface + interior, vs `vdb_tool -read MESH -mesh2ls d=N` on the same file.
# Goal at 512: <= 0.5x vdb_tool's wall time. Also 256 and 1024, and peak memory.
echo
echo "== voxelize: 200,000-facet knot, surface + interior, vs vdb_tool -mesh2ls (goal at 512: <= 0.5x)"
knot=$work/knot200k.stl
[ -f "$knot" ] || "$HOVOX" generate knot facets=200000 -o "$knot"
for d in 256 512 1024; do
    t_h=$(median vox_hovox_$d "$HOVOX" voxelize "$knot" --dims $d -o "$work/knot$d.vdb" -q)
    t_v=$(median vox_vdbtool_$d vdb_tool -read "$knot" -mesh2ls d=$d)
    m_h=$(peak_rss "$HOVOX" voxelize "$knot" --dims $d -o "$work/knot$d.vdb" -q)
    m_v=$(peak_rss vdb_tool -read "$knot" -mesh2ls d=$d)
    printf "dims %-5s hovox %7.3f s (%6.1f MiB)   vdb_tool %7.3f s (%6.1f MiB)   ratio %sx\n" \
        "$d" "$t_h" "$m_h" "$t_v" "$m_v" "$(ratio "$t_h" "$t_v")"
done
echo "(hovox: voxelize + write the .vdb; vdb_tool: read + narrow-band level set, no write)"
