#!/bin/sh
# scripts/bench/colour_depth_ab.sh OLD NEW [ROUNDS] - what the per-pixel colour depth (issue 29,
# colour.depth) costs: two hovox binaries, before and after, interleaved, CPU seconds (user + sys)
# and their medians over ROUNDS (default 3) of
#   paint: voxelize the bench's textured knot --dims 160 --colour-depth 1 (each binary its own model),
#   tray-only: the bench tray (gears, shafts, three painted knots) from those models, layers 400:430,
#   mesh: the bench tray painting the textured knot itself (colour.json), layers 400:430.
# Needs the bench's colour work directory (BENCH_DIR, default build/bench; made by
# `BENCH_ONLY=colour make bench`). Not a bench section (it needs two binaries).
set -eu
old=$1 new=$2 rounds=${3:-3}
cw=${BENCH_DIR:-build/bench}/colour
out=$(mktemp -d)
cpu() { /usr/bin/time -f "%U %S" -o "$out/t" "$@" >/dev/null 2>&1; awk '{ printf "%.2f", $1 + $2 }' "$out/t"; }
med() { printf '%s\n' "$@" | sort -n | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
for b in old new; do
    eval "h=\$$b"
    "$h" voxelize "$cw/knotc.obj" --dims 160 --colour-depth 1 -o "$out/knot_$b.vdb" -q >/dev/null
    sed "s#\"model\": \"knot_colour.vdb\"#\"model\": \"$out/knot_$b.vdb\"#" "$cw/painted.json" >"$cw/ab_$b.json"
done
po="" pn="" to="" tn="" mo="" mn=""
i=0
while [ $i -lt "$rounds" ]; do
    po="$po $(cpu "$old" voxelize "$cw/knotc.obj" --dims 160 --colour-depth 1 -o "$out/p_old.vdb" -q)"
    pn="$pn $(cpu "$new" voxelize "$cw/knotc.obj" --dims 160 --colour-depth 1 -o "$out/p_new.vdb" -q)"
    rm -f "$out/p_old.vdb" "$out/p_new.vdb"
    to="$to $(cpu "$old" tray "$cw/ab_old.json" -o "$out/t_old" --layers 400:430 --force -q)"
    tn="$tn $(cpu "$new" tray "$cw/ab_new.json" -o "$out/t_new" --layers 400:430 --force -q)"
    mo="$mo $(cpu "$old" tray "$cw/colour.json" -o "$out/m_old" --layers 400:430 --force -q)"
    mn="$mn $(cpu "$new" tray "$cw/colour.json" -o "$out/m_new" --layers 400:430 --force -q)"
    i=$((i + 1))
done
# shellcheck disable=SC2086
{
    echo "paint knot     old $(med $po) s  new $(med $pn) s  (runs old:$po new:$pn)"
    echo "tray-only      old $(med $to) s  new $(med $tn) s  (runs old:$to new:$tn)"
    echo "tray from mesh old $(med $mo) s  new $(med $mn) s  (runs old:$mo new:$mn)"
}
rm -rf "$out" "$cw/ab_old.json" "$cw/ab_new.json"
