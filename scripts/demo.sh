#!/bin/sh
# scripts/demo.sh - `make demo`: the gear sample end to end on its built-in defaults (Wu's
# third example: mesh, voxels, two grading sources, AGS and HO unions, profiles), plus the mesh
# reports of the sample meshes.
set -eu
: "${HOVOX:=build/hovox}"
out=${DEMO_OUT:-build/demo}
rm -rf "$out"
mkdir -p "$out"
echo "== mesh reports of the sample meshes"
"$HOVOX" info samples/*.stl
echo
echo "== Wu's gear (samples/wu_gear.lua)"
"$HOVOX" run samples/wu_gear.lua "$out"
echo
echo "demo outputs in $out/:"
ls "$out"
