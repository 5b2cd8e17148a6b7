#!/bin/sh
# scripts/demo.sh - `make demo`: the main job on built-in defaults.
set -eu
: "${HOVOX:=build/hovox}"
out=${DEMO_OUT:-build/demo}
mkdir -p "$out"
echo "== mesh reports of the sample meshes"
"$HOVOX" info samples/*.stl
echo
echo "== Wu's gear (bore 9.54 mm, tip radius 39.45 mm, height 39.45 mm), generated"
"$HOVOX" generate gear -o "$out/gear.stl"
"$HOVOX" info "$out/gear.stl"
echo
echo "demo outputs are in $out/"
