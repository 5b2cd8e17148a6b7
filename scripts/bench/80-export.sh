# scripts/bench/80-export.sh - issue 9: export the graded gear at 256 voxels to .vti (image
# data over its bounding box) and .vtu (one hexahedron per occupied voxel, and 2x2x2 blocks):
# wall time, peak memory and file size. Three materials (Wu's gear grading along the z axis,
# PolyJet-like properties), both mixing rules: 10 arrays. No anchor: the split between
# hovox building the arrays and VTK's XML writer (zlib) comes from bench_export.
echo
echo "== export: gear at 256 voxels, 3 materials, 10 arrays (time, peak memory, file size)"
gear=$work/gear.stl
[ -f "$gear" ] || "$HOVOX" generate gear -o "$gear" >/dev/null
vox=$work/gear256.vdb
[ -f "$vox" ] || "$HOVOX" voxelize "$gear" --dims 256 -o "$vox" -q >/dev/null
model=$work/gear256_graded.vdb
if ! "$HOVOX" grade --help >/dev/null 2>&1; then
    echo "(skipped: hovox grade is not available in this build)"
else
    # Wu's gear: radial gradient around the z axis (d- 9.54, dg 9.54, d+ 20.37), Ms, Me as Wu
    [ -f "$model" ] || "$HOVOX" grade "$vox" -o "$model" -q --materials vero,agilus,white \
        --frf axis:0,0,0:0,0,1 --ranges 9.54,9.54,20.37 --ms 0,0.9,0.1 --me 0.9,0,0.1 \
        --property vero:density=1180:kg/m^3 --property vero:youngs_modulus=2.5e9:Pa \
        --property vero:poisson_ratio=0.38:1 --property agilus:density=1140:kg/m^3 \
        --property agilus:youngs_modulus=6e5:Pa --property agilus:poisson_ratio=0.49:1 \
        --property white:density=1175:kg/m^3 --property white:youngs_modulus=2.2e9:Pa \
        --property white:poisson_ratio=0.38:1 >/dev/null
    for spec in "vti:" "vtu:" "vtu:--coarsen 2"; do
        ext=${spec%%:*}
        extra=${spec#*:}
        tag=$ext$(echo "$extra" | tr -d ' -')
        out=$work/gear256_$tag.$ext
        # shellcheck disable=SC2086
        t=$(median export_$tag "$HOVOX" export "$model" -o "$out" -q $extra)
        # shellcheck disable=SC2086
        m=$(peak_rss "$HOVOX" export "$model" -o "$out" -q $extra)
        printf "%-16s %7.3f s  (%6.1f MiB peak)  %6.1f MB  %s\n" "$ext $extra" "$t" "$m" \
            "$(awk -v b="$(wc -c <"$out")" 'BEGIN { printf "%.1f", b / 1e6 }')" \
            "$("$HOVOX" export "$model" -o "$out" --dry-run $extra | awk '/^image|^mesh/ {$1 = ""; print}')"
    done
    drv=$BUILD/bench-tools/bench_export
    if [ -x "$drv" ]; then
        for ext in vti vtu; do
            "$drv" "$model" "$work/gear256_drv.$ext" --runs "$runs" | awk -v e="$ext" \
                '/^export/ {printf "  %s: build arrays %s s (hovox), VTK XML + zlib write %s s (medians)\n", e, $6, $8}'
        done
    fi
    echo "(wall time includes loading the .vdb, ~0.3 s; zlib level 1 by default, --level 9 for smaller files)"
fi
