#!/bin/sh
# scripts/demo.sh - `make demo`: the gear sample end to end on its built-in defaults (Wu's
# third example: mesh, voxels, two grading sources, AGS and HO unions, profiles), plus the mesh
# reports of the sample meshes.
set -eu
: "${HOVOX:=build/hovox}"
out=${DEMO_OUT:-build/demo}
# clear an earlier demo's outputs only: the directory is ours when it holds the demo's marker
if [ -d "$out" ] && [ -n "$(ls -A "$out")" ]; then
    if [ ! -f "$out/.hovox-demo" ]; then
        echo "demo: $out exists and is not an earlier demo's output; choose another DEMO_OUT" >&2
        exit 1
    fi
    rm -rf "$out"
fi
mkdir -p "$out"
: >"$out/.hovox-demo"
echo "== mesh reports of the sample meshes"
"$HOVOX" info samples/*.stl
echo
echo "== Wu's gear (samples/wu_gear.lua)"
"$HOVOX" run samples/wu_gear.lua "$out"
echo
echo "demo outputs in $out/:"
ls "$out"
