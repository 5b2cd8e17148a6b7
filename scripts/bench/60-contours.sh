# scripts/bench/60-contours.sh - issue 6: contours of a 200,000-facet mesh (tube around a torus
# knot) at 0.027 mm layers with the WDG slicer, vs PrusaSlicer's SLA export of the same STL at
# the same layer height (supports and pad off; it slices and rasterizes every layer: the
# closest runnable anchor). Goal: contour extraction alone <= 0.25x PrusaSlicer's export.
echo
echo "== contours: 200,000-facet knot, 0.027 mm layers, vs prusa-slicer --export-sla (goal: extraction <= 0.25x)"
knot=$work/knot200k.stl
[ -f "$knot" ] || "$HOVOX" generate knot facets=200000 -o "$knot"
t_cli=$(median contours_cli "$HOVOX" contours "$knot" --layer-height 0.027 -o "$work/knot.cli" -q)
m_cli=$(peak_rss "$HOVOX" contours "$knot" --layer-height 0.027 -o "$work/knot.cli" -q)
t_bin=$(median contours_cli_bin "$HOVOX" contours "$knot" --layer-height 0.027 --binary -o "$work/knot_bin.cli" -q)
drv=$BUILD/bench-tools/bench_contours
if [ -x "$drv" ]; then
    # the driver reports medians of its own runs: build (WDG + z index), slice (all layers)
    "$drv" "$knot" 0.027 --runs "$runs" >"$work/contours_driver.txt"
    t_x=$(awk '/^load/ {print $8}' "$work/contours_driver.txt")
    t_wdg=$(awk '/^load/ {print $4}' "$work/contours_driver.txt")
    t_sl=$(awk '/^load/ {print $6}' "$work/contours_driver.txt")
    nl=$(awk '/^facets/ {print $4}' "$work/contours_driver.txt")
fi
# PrusaSlicer: the object (86 x 90 mm) must fit the display; 96 x 96 mm at 2048 x 2048 px keeps
# the default SL1 pixel pitch (0.047 mm). Slow (~45 s a run), so at most 3 runs.
saved_runs=$runs
runs=$((runs < 3 ? runs : 3))
t_p=$(median contours_prusa prusa-slicer --export-sla --printer-technology SLA --layer-height 0.027 \
    --initial-layer-height 0.027 --no-supports-enable --no-pad-enable --display-width 96 \
    --display-height 96 --display-pixels-x 2048 --display-pixels-y 2048 \
    --bed-shape 0x0,96x0,96x96,0x96 --center 48,48 --loglevel 0 -o "$work/knot.sl1" "$knot")
runs=$saved_runs
printf "hovox contours -o .cli (ASCII)  %8.3f s (%6.1f MiB)  STL load + WDG + slice + write %s MB\n" \
    "$t_cli" "$m_cli" "$(($(wc -c <"$work/knot.cli") / 1000000))"
printf "hovox contours -o .cli --binary %8.3f s\n" "$t_bin"
if [ -n "${t_x:-}" ]; then
    printf "contour extraction alone        %8.3f s  (WDG + z index %s s, %s layers %s s; bench_contours)\n" \
        "$t_x" "$t_wdg" "$nl" "$t_sl"
fi
printf "prusa-slicer --export-sla       %8.3f s  (slice + rasterize, supports and pad off)\n" "$t_p"
[ -n "${t_x:-}" ] && echo "ratio extraction / prusa        $(ratio "$t_x" "$t_p")x"
echo "ratio hovox contours CLI / prusa $(ratio "$t_cli" "$t_p")x"
