# scripts/bench/98-colour.sh - issue 29: the bench tray with its three knots textured in colour
# (scripts/bench/textured_knot.py: a 256 x 256 texture of 65,536 colours; painted 1 mm deep over a
# white core; six resins, 4-bit layers) against the same tray graded without colour (three resins,
# 2-bit layers). Goal: <= 1.5x.
# What each user pays, from the knot's mesh (the headline): a user with a textured mesh runs `tray`
# on the mesh, which voxelizes and paints it inside the tray; a user with graded materials first
# makes the model (`voxelize` + `grade`, timed in each round) and then runs `tray` on it. Both
# sides also printed tray-only, from models made beforehand: the graded knot.vdb against the
# knot painted by `voxelize --colour-depth 1` on the same 160-voxel grid (knot_colour.vdb). The
# gears and shafts are the same graded models on both sides.
# The trays run in rounds (graded, colour from the mesh, colour from the painted model),
# BENCH_COLOUR_RUNS rounds (default 1: a whole tray takes minutes); medians over the rounds.
# BENCH_COLOUR_LAYERS=a:b cuts every tray to those layers. Wall and CPU (user + sys) both, with
# their ratios: CPU is the steadier on a loaded machine.
# Kept in $work/colour for later runs and scripts/bench/colour_depth_ab.sh: knotc.obj,
# knot_colour.vdb, colour.json, painted.json. Everything else this section makes goes into a
# directory of its own (run.XXXXXX), removed at the end: nothing it did not make is deleted or
# overwritten.
echo
echo "== colour: the bench tray with its knots textured in colour vs graded without colour (goal: <= 1.5x)"
echo "  from the knot's mesh: tray on the textured mesh (paints it) vs voxelize + grade + tray; tray-only: both from models made beforehand"
bench_tray_parts "$work/tray"
cw="$work/colour"
mkdir -p "$cw"
[ -f "$cw/knotc.obj" ] || /usr/bin/python3 "$here/bench/textured_knot.py" "$work/tray/knot.stl" "$cw/knotc.obj"
# painted by this build every time: a model painted by an older build (no colour.depth grid) would
# print by the older path and make the tray-only side look cheaper than it is
"$HOVOX" voxelize "$cw/knotc.obj" --dims 160 --colour-depth 1 -o "$cw/knot_colour.vdb" -q >/dev/null
run=$(mktemp -d "$cw/run.XXXXXX")
t_paint=$(median colour_paint "$HOVOX" voxelize "$cw/knotc.obj" --dims 160 --colour-depth 1 -o "$run/paint.vdb" -q)
# one string: hyperfine runs it through a shell
make_graded="'$HOVOX' voxelize '$work/tray/knot.stl' --dims 160 -o '$run/occ.vdb' -q >/dev/null && '$HOVOX' grade '$run/occ.vdb' -o '$run/grade.vdb' --materials A,B,C --frf contour --ranges 0,4,0 --ms 1,0,0 --me 0,0.5,0.5 -q"
t_grade=$(median colour_grade "$make_graded")
echo "  knot painted 1 mm deep         $t_paint s   voxelized and graded $t_grade s   ratio $(ratio "$t_paint" "$t_grade")x"
for kind in graded colour painted; do
    # paths in a job file are relative to it: the graded job lives in $run with its model
    dir=$cw up=..
    case $kind in
    graded) dir=$run up=../.. knot='"model": "grade.vdb", "mesh": "../../tray/knot.stl"' ;;
    colour) knot='"mesh": "knotc.obj"' ;; # no model: the tray paints the textured mesh itself
    painted) knot='"model": "knot_colour.vdb", "mesh": "knotc.obj"' ;;
    esac
    cat >"$dir/$kind.json" <<EOF
{"schema": 1, "profile": "j750", "arrange": "all",
 "resin": {"A": "VeroCyan-V", "B": "VeroMagenta-V", "C": "VeroYellow-V"},
 "parts": [{"model": "$up/tray/gear.vdb", "mesh": "$up/tray/gear.stl", "copies": 6},
           {"model": "$up/tray/shaft.vdb", "mesh": "$up/tray/shaft.stl", "copies": 3},
           {$knot, "copies": 3}]}
EOF
done
lay=""
[ -n "${BENCH_COLOUR_LAYERS:-}" ] && lay="--layers $BENCH_COLOUR_LAYERS"
tm="" tg="" te="" tc="" tp="" cm="" cg="" ce="" cc="" cp="" i=0
while [ $i -lt "${BENCH_COLOUR_RUNS:-1}" ]; do
    # the graded user's model, made again each round (its time is part of that user's cost);
    # each run gives its wall and CPU time (user + sys)
    # shellcheck disable=SC2046
    set -- $(wall_cpu sh -c "$make_graded")
    m=$1 mc=$2
    # shellcheck disable=SC2046,SC2086
    set -- $(wall_cpu "$HOVOX" tray "$run/graded.json" -o "$run/graded" $lay --force -q)
    g=$1 gc=$2
    tm="$tm $m" tg="$tg $g" te="$te $(awk -v a="$m" -v b="$g" 'BEGIN { printf "%.4f", a + b }')"
    cm="$cm $mc" cg="$cg $gc" ce="$ce $(awk -v a="$mc" -v b="$gc" 'BEGIN { printf "%.4f", a + b }')"
    # shellcheck disable=SC2046,SC2086
    set -- $(wall_cpu "$HOVOX" tray "$cw/colour.json" -o "$run/colour" $lay --force -q)
    tc="$tc $1" cc="$cc $2"
    # shellcheck disable=SC2046,SC2086
    set -- $(wall_cpu "$HOVOX" tray "$cw/painted.json" -o "$run/painted" $lay --force -q)
    tp="$tp $1" cp="$cp $2"
    i=$((i + 1))
done
# shellcheck disable=SC2086
t_m=$(median_of $tm) t_g=$(median_of $tg) t_e=$(median_of $te) t_c=$(median_of $tc) t_p=$(median_of $tp)
# shellcheck disable=SC2086
c_m=$(median_of $cm) c_g=$(median_of $cg) c_e=$(median_of $ce) c_c=$(median_of $cc) c_p=$(median_of $cp)
echo "  ${BENCH_COLOUR_LAYERS:+layers $BENCH_COLOUR_LAYERS, }medians of ${BENCH_COLOUR_RUNS:-1} round(s), wall (CPU = user + sys)"
echo "  from the mesh: graded knot made $t_m s + tray (3 resins) $t_g s = $t_e s  (runs:$te)"
echo "                 CPU $c_m s + $c_g s = $c_e s  (runs:$ce)"
echo "  from the mesh: tray on the textured knot (6 resins)  $t_c s  (runs:$tc)"
echo "                 CPU $c_c s  (runs:$cc)"
echo "  ratio colour / graded, from the mesh    $(ratio "$t_c" "$t_e")x wall, $(ratio "$c_c" "$c_e")x CPU"
echo "  tray-only: graded tray $t_g s, tray of the painted model $t_p s  (runs:$tp)"
echo "             CPU $c_g s, $c_p s  (runs:$cp)"
echo "  ratio colour / graded, tray-only        $(ratio "$t_p" "$t_g")x wall, $(ratio "$c_p" "$c_g")x CPU"
rm -rf "$run"
