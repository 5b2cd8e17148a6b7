# scripts/bench/97-scan.sh - issue 30: a scanned volume straight to a J750 stack.
# A synthetic 512 x 512 x 400 volume (int16 NIfTI, 0.2 mm samples: a 102 x 102 x 80 mm grid, a head-like
# ellipsoid of 96 x 92 x 76 mm with a skull shell, by scripts/bench/make_scan.py) printed with a Hounsfield lookup
# table: `hovox layers VOLUME --iso -480 --lut bone.csv --profile j750`. Goal: >= 2e8 printer
# voxels/s (width x height x layers of the stack over the wall time) on 2 cores, peak RSS <= the
# volume (as floats) + 1 GiB. Anchor: the same stack in --mode mask (the shape alone), same run.
# BENCH_SCAN_RUNS (default 3: a run takes minutes), BENCH_SCAN_VOLUME (another volume, to try it).
echo
echo "== scan: 512 x 512 x 400 volume -> J750 stack (goal: >= 2e8 printer voxels/s, peak <= volume + 1 GiB)"
vol=${BENCH_SCAN_VOLUME:-$work/scan512.nii}
[ -f "$vol" ] || /usr/bin/python3 "$here/bench/make_scan.py" "$vol"
printf 'HU,VeroClear,Agilus30Clear,VeroPureWhite\n-1000,1,0,0\n0,0,1,0\n300,0,1,0\n1000,0,0,1\n' >"$work/scan_bone.csv"
saved_runs=$runs
runs=${BENCH_SCAN_RUNS:-3}
t_s=$(median scan_layers "$HOVOX" layers "$vol" --iso -480 --lut "$work/scan_bone.csv" --profile j750 -o "$work/scan_stack" --force -q)
t_m=$(median scan_mask "$HOVOX" layers "$vol" --iso -480 --mode mask --profile j750 -o "$work/scan_mask" --force -q)
runs=$saved_runs
m_s=$(peak_rss "$HOVOX" layers "$vol" --iso -480 --lut "$work/scan_bone.csv" --profile j750 -o "$work/scan_stack" --force -q)
px=$(/usr/bin/python3 -c "import json,sys; m=json.load(open(sys.argv[1])); print(m['width'] * m['height'] * len(m['layers']), len(m['layers']), m['width'], m['height'])" \
    "$work/scan_stack/manifest.json")
read -r n_px n_l w h <<EOF2
$px
EOF2
vol_mib=$(awk 'BEGIN { printf "%.1f", 512 * 512 * 400 * 4 / 1048576 }')
printf "hovox layers VOLUME --lut (halftone) %8.3f s  %s layers of %s x %s: %s printer voxels/s\n" "$t_s" "$n_l" "$w" "$h" \
    "$(awk -v n="$n_px" -v t="$t_s" 'BEGIN { printf "%.3g", n / t }')"
printf "hovox layers VOLUME --mode mask      %8.3f s  (anchor: the shape alone)\n" "$t_m"
echo "ratio halftone / mask               $(ratio "$t_s" "$t_m")x"
printf "peak RSS                            %8.1f MiB (the volume as floats: %s MiB; goal <= %s MiB)\n" "$m_s" "$vol_mib" \
    "$(awk -v v="$vol_mib" 'BEGIN { printf "%.1f", v + 1024 }')"
