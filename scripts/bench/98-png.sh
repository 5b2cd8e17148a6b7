# scripts/bench/98-png.sh - issue 26 item 3: one PNG encoder for stacks and renders, chosen here.
# 1. Encoders on real stack layers: 16 layers of the bench tray (95-tray.sh's parts on the J750
#    plate, 11,575 x 4,606, 2-bit indexed, pHYs 600 x 300 dpi), each encoded by hovox's encoder
#    (libdeflate), libpng and libspng at zlib levels 1 (the stacks' default) and 6, one thread,
#    medians of $runs runs; every output is decoded by libpng and compared with the layer.
#    (A hand-written Huffman coder, src/image/png_fast.c, was measured here before it was removed:
#    22-26 ms a layer against 23-37 ms for libdeflate, but 4.7x the bytes, and slower end to end.)
# 2. The tray end to end (layers 400:464): wall time, peak RSS, bytes.
echo
echo "== PNG encoders on 16 bench-tray layers (issue 26 item 3; one encoder: hovox's, libdeflate)"
tw="$work/tray"
drv=$BUILD/bench-tools/bench_png
if [ ! -x "$drv" ] || [ ! -f "$tw/tray.json" ]; then
    echo "skipped: needs $drv (make bench-tools) and the bench tray (BENCH_ONLY=tray first)"
else
    "$HOVOX" tray "$tw/tray.json" -o "$tw/png_layers" --layers 400:416 --force -q >/dev/null
    for level in 1 6; do
        "$drv" "$runs" "$level" "$tw"/png_layers/layer-*.png
    done
    t=$( { /usr/bin/time -f "%e %M" "$HOVOX" tray "$tw/tray.json" -o "$tw/png_e2e" --layers 400:464 --force -q \
        >/dev/null; } 2>&1 | tail -n 1)
    echo "  hovox tray --layers 400:464     ${t% *} s  $(awk -v k="${t#* }" 'BEGIN { printf "%.1f", k / 1024 }') MiB peak RSS  $(du -sb "$tw/png_e2e" | awk '{ printf "%.1f MiB", $1 / 1048576 }')"
    rm -rf "$tw/png_layers" "$tw/png_e2e"
fi
