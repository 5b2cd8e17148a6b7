# scripts/bench/98-colour.sh - issue 29: the bench tray with its three knots textured in colour
# (scripts/bench/textured_knot.py: a 256 x 256 texture of 65,536 colours; the part is the mesh
# alone, which the tray voxelizes and paints 1 mm deep over a white core, as `layers MESH` would;
# six resins) against the same tray graded without colour (three resins, graded models made
# beforehand). Goal: <= 1.5x.
# The two trays run alternately, BENCH_COLOUR_RUNS times each (default 1: a whole tray takes
# minutes); BENCH_COLOUR_LAYERS=a:b cuts both to those layers. Painting the knot is timed against
# voxelizing and grading it.
echo
echo "== colour: the bench tray with its knots textured in colour vs graded without colour (goal: <= 1.5x)"
bench_tray_parts "$work/tray"
cw="$work/colour"
mkdir -p "$cw"
if [ ! -f "$cw/knot_colour.vdb" ]; then
    /usr/bin/python3 "$here/bench/textured_knot.py" "$work/tray/knot.stl" "$cw/knotc.obj"
    "$HOVOX" voxelize "$cw/knotc.obj" --dims 160 --colour-depth 1 -o "$cw/knot_colour.vdb" -q >/dev/null
fi
t_paint=$(median colour_paint "$HOVOX" voxelize "$cw/knotc.obj" --dims 160 --colour-depth 1 -o "$cw/paint.vdb" -q)
# one string: hyperfine runs it through a shell
t_grade=$(median colour_grade "'$HOVOX' voxelize '$work/tray/knot.stl' --dims 160 -o '$cw/occ.vdb' -q >/dev/null && '$HOVOX' grade '$cw/occ.vdb' -o '$cw/grade.vdb' --materials A,B,C --frf contour --ranges 0,4,0 --ms 1,0,0 --me 0,0.5,0.5 -q")
echo "  knot painted 1 mm deep         $t_paint s   voxelized and graded $t_grade s   ratio $(ratio "$t_paint" "$t_grade")x"
for kind in graded colour; do
    if [ $kind = graded ]; then knot='"model": "../tray/knot.vdb", "mesh": "../tray/knot.stl"'
    else knot='"mesh": "knotc.obj"'; fi # no model: the tray paints the textured mesh itself
    cat >"$cw/$kind.json" <<EOF
{"schema": 1, "profile": "j750", "arrange": "all",
 "resin": {"A": "VeroCyan-V", "B": "VeroMagenta-V", "C": "VeroYellow-V"},
 "parts": [{"model": "../tray/gear.vdb", "mesh": "../tray/gear.stl", "copies": 6},
           {"model": "../tray/shaft.vdb", "mesh": "../tray/shaft.stl", "copies": 3},
           {$knot, "copies": 3}]}
EOF
done
lay=""
[ -n "${BENCH_COLOUR_LAYERS:-}" ] && lay="--layers $BENCH_COLOUR_LAYERS"
tg="" tc="" i=0
while [ $i -lt "${BENCH_COLOUR_RUNS:-1}" ]; do
    # shellcheck disable=SC2086
    tg="$tg $(wall "$HOVOX" tray "$cw/graded.json" -o "$cw/graded" $lay --force -q)"
    # shellcheck disable=SC2086
    tc="$tc $(wall "$HOVOX" tray "$cw/colour.json" -o "$cw/colour" $lay --force -q)"
    i=$((i + 1))
done
# shellcheck disable=SC2086
t_g=$(median_of $tg)
# shellcheck disable=SC2086
t_c=$(median_of $tc)
echo "  tray graded (3 resins)         $t_g s  (runs:$tg)  ${BENCH_COLOUR_LAYERS:+layers $BENCH_COLOUR_LAYERS}"
echo "  tray, knots in colour (6)      $t_c s  (runs:$tc)"
echo "  ratio colour / graded          $(ratio "$t_c" "$t_g")x"
rm -rf "$cw/graded" "$cw/colour" "$cw/paint.vdb" "$cw/occ.vdb" "$cw/grade.vdb"
