# issue 16's multi-body case end to end from a 3MF: a Vero shell with a cavity and the Agilus
# core filling it (two objects with two base materials, tests/data/good/core_in_shell.3mf) voxelize
# to two regions with their materials, grade to them without sources, and the stack printed from
# the same 3MF as --mesh (contours per body, their union constraining the layers) holds both
# materials at mid-height: the core's (palette 2, 'A') inside the shell's (palette 1, 'V')
m=tests/data/good/core_in_shell.3mf
$HOVOX voxelize $m -o "$TMP/a.vdb" --voxel-size 0.5 &&
$HOVOX grade "$TMP/a.vdb" -o "$TMP/g.vdb" -q &&
$HOVOX layers "$TMP/g.vdb" --mesh $m -o "$TMP/stack" --dpi 50,50 --layer-height 1 &&
# the target is a mean of float fractions: its last digits follow the build's float contraction
# (the sanitizer build differs past the 8th), so it is shown to 7 decimals
sed -n '/"materials"/,/]/p' "$TMP/stack/manifest.json" | sed -E 's/("target": [0-9]+\.[0-9]{7})[0-9]*/\1/' &&
/usr/bin/python3 tests/cli/png_palette_map.py "$TMP/stack/layer-00005.png" '.VA?'
echo "rc=$?"
