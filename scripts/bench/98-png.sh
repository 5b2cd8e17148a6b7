# scripts/bench/98-png.sh - issue 26 item 3: one PNG encoder for stacks and renders, chosen here.
# hv_png_encode (src/image/png.c) has two ways to the zlib stream: libdeflate, and a span coder
# (one Huffman block; a blank row costs a few bits and no reading; copies at the few distances the
# drawn bytes repeat at, found per layer, and literals) that it takes for sparse indexed or
# sub-byte layers. A hand-written coder stays only if it is at least 1.3x faster end to end on a
# bench tray (issue 26), and its files should be within 1.15x libdeflate's (issue 26 follow-up), so:
# 1. Encoders on real stack layers, one thread, medians of $runs runs, every output decoded by
#    libpng and compared with the layer: hovox's encoder as it picks, the same with its span coder
#    off (HOVOX_PNG_SPARSE=0: libdeflate on every layer), libpng and libspng. 16 layers of the
#    bench tray (dense: 12 parts across the J750 plate, 2-bit) at zlib levels 1 (the stacks'
#    default) and 6, and 8 layers of the README's tray (sparse: 4 parts on 6% of the plate, 4-bit).
# 2. End to end, the span coder on and off, interleaved, medians of min($runs, 3): the README's
#    tray (1,461 layers) and the bench tray's layers 400:464; wall time, ratio, bytes.
echo
echo "== PNG encoders on tray layers (issue 26 item 3; one encoder, two ways: libdeflate and the span coder)"
tw="$work/tray"
drv=$BUILD/bench-tools/bench_png
if [ ! -x "$drv" ] || [ ! -f "$tw/tray.json" ]; then
    echo "skipped: needs $drv (make bench-tools) and the bench tray (BENCH_ONLY=tray first)"
else
    rw="$work/readme_tray"
    mkdir -p "$rw"
    inputs=$(cd "$here/.." && pwd)/tests/readme/stack_inputs.sh
    hv_dir=$(cd "$(dirname "$HOVOX")" && pwd)
    (cd "$rw" && PATH="$hv_dir:$PATH" sh "$inputs")
    echo "  the bench tray (dense)"
    "$HOVOX" tray "$tw/tray.json" -o "$tw/png_layers" --layers 400:416 --force -q >/dev/null
    for level in 1 6; do
        "$drv" "$runs" "$level" "$tw"/png_layers/layer-*.png
    done
    echo "  the README's tray (sparse)"
    "$HOVOX" tray "$rw/job.json" -o "$rw/png_layers" --force -q >/dev/null
    "$drv" "$runs" 1 "$rw"/png_layers/layer-00010.png "$rw"/png_layers/layer-00200.png \
        "$rw"/png_layers/layer-00400.png "$rw"/png_layers/layer-00600.png "$rw"/png_layers/layer-00800.png \
        "$rw"/png_layers/layer-01000.png "$rw"/png_layers/layer-01200.png "$rw"/png_layers/layer-01400.png
    rm -rf "$tw/png_layers" "$rw/png_layers"
    n=$((runs < 3 ? runs : 3))
    e2e() { # LABEL JOB [OPTIONS]: hovox's encoder as it picks, then libdeflate alone, interleaved
        label=$1
        shift
        ta="" tb="" i=0
        while [ $i -lt "$n" ]; do
            ta="$ta $(wall "$HOVOX" tray "$@" -o "$work/png_e2e_a" --force -q)"
            tb="$tb $(wall env HOVOX_PNG_SPARSE=0 "$HOVOX" tray "$@" -o "$work/png_e2e_b" --force -q)"
            i=$((i + 1))
        done
        # shellcheck disable=SC2086
        ma=$(median_of $ta)
        # shellcheck disable=SC2086
        mb=$(median_of $tb)
        sa=$(du -sb "$work/png_e2e_a" | awk '{ printf "%.1f MiB", $1 / 1048576 }')
        sb=$(du -sb "$work/png_e2e_b" | awk '{ printf "%.1f MiB", $1 / 1048576 }')
        printf "  %-34s hovox %8.2f s %10s   libdeflate only %8.2f s %10s   ratio %sx  (goal for a hand-written part: >= 1.3x)\n" \
            "$label" "$ma" "$sa" "$mb" "$sb" "$(ratio "$mb" "$ma")"
        rm -rf "$work/png_e2e_a" "$work/png_e2e_b"
    }
    echo "  end to end, median of $n (wall)"
    e2e "README tray (1,461 layers, sparse)" "$rw/job.json"
    e2e "bench tray 400:464 (dense)" "$tw/tray.json" --layers 400:464
fi
