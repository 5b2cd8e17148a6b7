# scripts/bench/40-edt.sh - issue 4: exact Euclidean distance transform of a solid ball
# (radius 0.45 n in an n^3 grid) vs scipy.ndimage.distance_transform_edt on the same mask, in
# the same run. Feature = the voxels outside the ball, so every inside voxel gets its distance
# to the outside, which is what scipy computes for the nonzero voxels of the mask. Both times
# are the transform alone (no file I/O, no interpreter start-up), medians; the outputs are
# compared. Goal at 512^3: <= 0.03x scipy's time on this machine's cores.
echo
echo "== edt: solid ball r = 0.45 n, exact EDT vs scipy.ndimage.distance_transform_edt (goal at 512^3: <= 0.03x)"
drv=$BUILD/bench-tools/bench_edt
helper=$here/bench/edt_scipy.py
if [ ! -x "$drv" ]; then
    echo "skipped: $drv not built (make bench-tools)"
else
    for n in 256 512; do
        mask=$work/ball$n.raw
        [ -f "$mask" ] || /usr/bin/python3 "$helper" make sphere $n "$mask"
        "$drv" "$mask" $n $n $n --invert --runs "$runs" --out "$work/ball$n.edt.f32" \
            >"$work/edt_hovox_$n.txt"
        t_h=$(awk '{for (i = 1; i < NF; ++i) if ($i == "median") print $(i + 1)}' "$work/edt_hovox_$n.txt")
        m_h=$(awk '{for (i = 1; i < NF; ++i) if ($i == "peak") print $(i + 1)}' "$work/edt_hovox_$n.txt")
        # scipy takes about 50 s at 512^3 (single-threaded): at most 3 runs there
        sruns=$runs
        [ $n -ge 512 ] && sruns=$((runs < 3 ? runs : 3))
        /usr/bin/python3 "$helper" time "$mask" $n --runs "$sruns" \
            --compare "$work/ball$n.edt.f32" >"$work/edt_scipy_$n.txt"
        t_s=$(awk '/^scipy/ {print $3}' "$work/edt_scipy_$n.txt")
        m_s=$(awk '/^scipy/ {print $12}' "$work/edt_scipy_$n.txt")
        diff=$(awk '/^max_abs_diff/ {print $2}' "$work/edt_scipy_$n.txt")
        dmax=$(awk '/^max_abs_diff/ {print $4}' "$work/edt_scipy_$n.txt")
        printf "%4s^3  hovox %7.3f s (%6.1f MiB, %s runs)   scipy %7.3f s (%6.1f MiB, %s runs)   ratio %sx   max |diff| %s (max distance %s)\n" \
            "$n" "$t_h" "$m_h" "$runs" "$t_s" "$m_s" "$sruns" "$(ratio "$t_h" "$t_s")" "$diff" "$dmax"
        rm -f "$work/ball$n.edt.f32"
    done
    echo "(transform alone, each run into a fresh output buffer: bench_edt on $(nproc) threads, float32;"
    echo " scipy single-threaded, float64)"
fi
