#!/bin/sh
# scripts/boolean_pictures.sh - the README's picture of each Boolean (issue 28): a plate 40 x 20 x
# 10 graded red (A) from its left end and a rod of radius 5 through it graded blue (B) from its
# axis, 0.5 mm voxels, combined by `hovox boolean` with each operation and rendered with the front
# half cut away (y < 10), so the cut face shows shape and material. Writes docs/boolean_<op>.png.
# Usage: sh scripts/boolean_pictures.sh [OUT_DIR]   (HOVOX: the binary, default build/hovox)
set -eu
: "${HOVOX:=build/hovox}"
case "$HOVOX" in /*) ;; *) HOVOX=$(pwd)/$HOVOX ;; esac
out=$(cd "${1:-docs}" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$HOVOX" generate box min=0,0,0 max=40,20,10 -o plate.stl >/dev/null
"$HOVOX" generate cylinder base=20,10,-1 axis=2 length=12 radius=5 segments=64 -o rod.stl >/dev/null
"$HOVOX" voxelize plate.stl --voxel-size 0.5 -o plate.vdb -q >/dev/null
"$HOVOX" voxelize rod.stl --voxel-size 0.5 -o rod.vdb -q >/dev/null
# nearest source wins where both apply (grade --blend nearest): the rod's axis is nearer than the
# plate's left end everywhere within 10 mm of it
"$HOVOX" grade plate.vdb -o a.vdb --materials A,B --colors '#d62728,#1f77b4' --frf plane:0,0,0:1,0,0 \
    --ranges 0,0,0 --ms 1,0 --me 1,0 >/dev/null
"$HOVOX" grade rod.vdb -o b.vdb --materials A,B --colors '#d62728,#1f77b4' --frf axis:20,10,0:0,0,1 \
    --ranges 0,0,0 --ms 0,1 --me 0,1 >/dev/null
for op in intersect union difference merge subtract; do
    "$HOVOX" boolean a.vdb "$op" b.vdb -o "$op.vdb" -q >/dev/null
    "$HOVOX" render "$op.vdb" --surface --clip 'y<10' --eye 5,-50,40 --target 20,10,5 --size 420,260 --aa 2 \
        -q -o "$out/boolean_$op.png" >/dev/null
    echo "wrote $out/boolean_$op.png"
done
