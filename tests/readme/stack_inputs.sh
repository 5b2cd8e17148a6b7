#!/bin/sh
# tests/readme/stack_inputs.sh - what the README's layers, tray and MPI examples take from the
# user, made when missing (a run of the whole README has made the gear already): Wu's gear graded
# as "Wu's gear" shows it, a small graded part, a graded shaft, a bracket and a pin for the tray,
# and job.json as the README shows it. Run in the scratch directory of tests/readme/run.py.
set -e
readme=$(dirname "$(readlink -f "$0")")/../../README.md
[ -f gear.stl ] || hovox generate gear -o gear.stl >/dev/null
[ -f gear.vdb ] || hovox voxelize gear.stl --dims 128 -o gear.vdb -q >/dev/null
[ -f gear_graded.vdb ] || hovox grade gear.vdb -o gear_graded.vdb --materials A,B,C \
    --frf axis:0,0,0:0,0,1 --ranges 9.54,9.54,20.37 --f 'd/dg' --ms 0,0.9,0.1 --me 0.9,0,0.1 \
    --frf plane:0,0,0:0,0,1 --ranges 3.18,22.26,14.01 --f 'd/dg' --ms 0,0.9,0.1 --me 0.9,0,0.1 -q
if [ ! -f part.vdb ]; then
    hovox generate box max=20,10,5 -o part.stl >/dev/null
    hovox voxelize part.stl --voxel-size 0.5 -o part_occ.vdb -q >/dev/null
    hovox grade part_occ.vdb -o part.vdb --materials A,B --frf plane:0,0,0:1,0,0 --ranges 0,20,0 --ms 1,0 --me 0,1 -q
fi
if [ ! -f shaft.vdb ]; then
    hovox generate cylinder length=60 radius=10 -o shaft.stl >/dev/null
    hovox voxelize shaft.stl --voxel-size 0.5 -o shaft_occ.vdb -q >/dev/null
    hovox grade shaft_occ.vdb -o shaft.vdb --materials A,B --frf axis:0,0,0:1,0,0 --ranges 0,10,0 --ms 1,0 --me 0,1 -q
fi
[ -f bracket.stl ] || hovox generate holed-box max=40,30,10 hole=6 -o bracket.stl >/dev/null
[ -f pin.stl ] || hovox generate cylinder axis=2 length=10 radius=2 -o pin.stl >/dev/null
# the job file: the README's own block (the one after "test-file: job.json")
[ -f job.json ] || awk '/test-file: job.json/ { on = 1; next } on && /^```json/ { copy = 1; next }
    copy && /^```/ { exit } copy { print }' "$readme" >job.json
