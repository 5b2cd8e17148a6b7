# scripts/bench/95-tray.sh - issue 14: a whole J750 tray.
# 1. The bench tray: 6 Wu gears, 3 Wu shafts lying along x, 3 torus knots, graded, auto-arranged
#    on the J750 plate; layers up to the tallest part (55 mm, 2,037 layers, ~1.1e11 tray voxels).
#    Goals on 2 cores: <= 3 min wall, <= 2 GiB peak RSS, >= 2e8 object voxels/s, >= 2e9 empty
#    plate voxels/s (a plate holding one 1 mm pin, 2,037 layers).
# 2. The full-height tray: the bench tray's arrangement in three storeys up to 199 mm (~7,370
#    layers), once, with --gcvf: time, RSS, zip size (past 4 GiB: ZIP64).
# 3. The same arrangement in mask mode against prusa-slicer --export-sla on the placed parts as
#    one STL (hovox tray --stl), the same pixels (490 x 390 mm display of 11,575 x 4,606) and
#    layers (0.027 mm). Goal: <= 0.3x its wall time.
echo
echo "== tray: 6 gears, 3 shafts, 3 knots, graded, arranged on the J750 plate (goals: <= 180 s, <= 2 GiB, >= 2e8 object vox/s, >= 2e9 empty vox/s)"
tw="$work/tray"
mkdir -p "$tw"
bench_tray_parts "$tw"
cat >"$tw/tray.json" <<'EOF'
{"schema": 1, "profile": "j750", "arrange": "all",
 "resin": {"A": "VeroCyan-V", "B": "VeroMagenta-V", "C": "VeroYellow-V"},
 "parts": [{"model": "gear.vdb", "mesh": "gear.stl", "copies": 6},
           {"model": "shaft.vdb", "mesh": "shaft.stl", "copies": 3},
           {"model": "knot.vdb", "mesh": "knot.stl", "copies": 3}]}
EOF
"$HOVOX" tray "$tw/tray.json" -o "$tw/stack" --dry-run | sed 's/^/  /'
# one run each (a run takes minutes); the blue-noise tile is cached by the earlier sections
t_tray=$( { /usr/bin/time -f "%e %M" "$HOVOX" tray "$tw/tray.json" -o "$tw/stack" --force --stl "$tw/placed.stl" -q \
    >/dev/null; } 2>&1 | tail -n 1)
secs=${t_tray% *}
rss=${t_tray#* }
/usr/bin/python3 - "$tw/stack/manifest.json" "$secs" "$rss" "$(du -sb "$tw/stack" | cut -f1)" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
secs, rss, size = float(sys.argv[2]), float(sys.argv[3]) / 1024, int(sys.argv[4])
obj = sum(p["object_pixels"] for p in m["parts"])
tray = m["width"] * m["height"] * (m["last"] - m["first"])
print("  hovox tray                     %8.1f s  %7.1f MiB peak RSS  %d layers of %d x %d, %.3g tray voxels"
      % (secs, rss, m["last"] - m["first"], m["width"], m["height"], tray))
print("  object voxels/s                %10.3g  (%.3g object voxels)" % (obj / secs, obj))
print("  tray voxels/s                  %10.3g" % (tray / secs))
print("  output                         %8.1f MiB (%d parts, %.1f%% of the plate)" % (size / 1048576, len(m["parts"]), 100 * m["utilisation"]))
PY
# issue 32 item 21: memory against threads. Layers 256 to 512 (32 runs of 8 layers, so 16
# threads all work; every part is in them), one run each: the dry run's estimate and the peak RSS.
# Threads beyond the cores change only the memory here, not the work.
echo "  threads  estimate      peak RSS   (layers 256:512; goal: at most 4 plates, one part's buffers a thread)"
for th in 2 8 16; do
    est=$("$HOVOX" tray "$tw/tray.json" -o "$tw/mem" --layers 256:512 --threads "$th" --dry-run 2>/dev/null |
        sed -n 's/^memory *about //p')
    /usr/bin/time -o "$tw/mem.rss" -f "%M" "$HOVOX" tray "$tw/tray.json" -o "$tw/mem$th" --layers 256:512 \
        --threads "$th" --force -q >/dev/null 2>&1
    r=$(tail -n 1 "$tw/mem.rss")
    printf "  %7s  %-12s %8.1f MiB\n" "$th" "$est" "$(awk -v k="$r" 'BEGIN { printf "%.1f", k / 1024 }')"
done
diff -r "$tw/mem2" "$tw/mem16" >/dev/null && echo "  the stacks of 2 and 16 threads are the same bytes" ||
    echo "  the stacks of 2 and 16 threads DIFFER"
rm -rf "$tw/mem2" "$tw/mem8" "$tw/mem16"
t_pin=$(median tray_empty "$HOVOX" tray -o "$tw/pin_stack" --part "$tw/pin.stl:VeroPureWhite@245,195" --force -q)
echo "  empty plate (one 1 mm pin)     $t_pin s  $(awk -v t="$t_pin" 'BEGIN { printf "%.3g", 11575 * 4606 * 2037 / t }') voxels/s"

if [ "${BENCH_PRUSA:-1}" = 1 ]; then
echo
echo "== tray in mask mode vs prusa-slicer --export-sla, same placed parts, pixels and layers (goal: <= 0.3x)"
# prusa-slicer takes minutes here: the two run alternately, at most 2 runs each, no warm-up
prusa() {
    wall timeout 1800 prusa-slicer --export-sla --printer-technology SLA --layer-height 0.027 \
        --initial-layer-height 0.027 --no-supports-enable --no-pad-enable --display-orientation landscape \
        --display-width 490 --display-height 390 --display-pixels-x 11575 --display-pixels-y 4606 \
        --bed-shape 0x0,490x0,490x390,0x390 --dont-arrange --loglevel 0 -o "$tw/tray.sl1" "$tw/placed.stl"
}
tm="" tp="" i=0
while [ $i -lt $((runs < 2 ? runs : 2)) ]; do
    tm="$tm $(wall "$HOVOX" tray "$tw/tray.json" -o "$tw/mask" --mode mask --force -q)"
    tp="$tp $(prusa || echo fail)"
    i=$((i + 1))
done
# shellcheck disable=SC2086
t_tm=$(median_of $tm)
echo "  hovox tray --mode mask         $t_tm s  $(ls "$tw/mask" | grep -c png) layers (runs:$tm)"
case "$tp" in
*fail*) echo "  prusa-slicer --export-sla      failed or took over 30 minutes on the 11,575 x 4,606 display" ;;
*)
    # shellcheck disable=SC2086
    t_pt=$(median_of $tp)
    echo "  prusa-slicer --export-sla      $t_pt s  $(unzip -l "$tw/tray.sl1" | grep -c 'png$') PNG layers in a zip (runs:$tp)"
    echo "  ratio hovox / prusa            $(ratio "$t_tm" "$t_pt")x"
    ;;
esac
fi # BENCH_PRUSA=0: no prusa-slicer comparison (it takes minutes a run)

if [ "${BENCH_FULL_TRAY:-1}" = 1 ]; then
    echo
    echo "== full-height tray: the bench tray's arrangement in three storeys (lifts 0, 72, 144 mm; up to 199 mm, ~7,370 layers), with --gcvf"
    /usr/bin/python3 - "$tw/stack/manifest.json" "$tw/full.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
files = {"gear.stl": "gear", "shaft.stl": "shaft", "knot.stl": "knot"}
parts = []
for z in (0, 72, 144):
    for p in m["parts"]:
        n = files[p["name"]]
        parts.append({"model": n + ".vdb", "mesh": n + ".stl", "at": p["at_mm"], "z": z})
json.dump({"schema": 1, "profile": "j750",
           "resin": {"A": "VeroCyan-V", "B": "VeroMagenta-V", "C": "VeroYellow-V"}, "parts": parts},
          open(sys.argv[2], "w"))
PY
    r=$( { /usr/bin/time -f "%e %M" "$HOVOX" tray "$tw/full.json" -o "$tw/full" --gcvf "$tw/full.zip" --force -q \
        >/dev/null; } 2>&1 | tail -n 1)
    echo "  hovox tray --gcvf              ${r% *} s  $(awk -v k="${r#* }" 'BEGIN { printf "%.1f", k / 1024 }') MiB peak RSS  $(ls "$tw/full" | grep -c png) layers"
    echo "  zip                            $(du -b "$tw/full.zip" | awk '{ printf "%.2f GiB", $1 / 1073741824 }'), $(unzip -l "$tw/full.zip" | tail -n 1 | awk '{print $2}') entries"
    rm -rf "$tw/full" "$tw/full.zip"
fi
