# an assembly (an Agilus core in a Vero shell, made by a Lua script, see grade_assembly) graded to
# its bodies' materials, printed at 50 dpi with 1 mm layers: the layer at mid-height holds both
# materials, the core's (palette 1, 'A') inside the shell's (palette 2, 'V'). The shape is the
# multi-body mesh the model records (issue 28; no --mesh); Lua prints it from that mesh too
# (tests/lua/test_assembly.lua), and the OBJ (assembly.obj) once hovox reads OBJ.
$HOVOX run tests/lua/scripts/assembly.lua "$TMP" &&
$HOVOX grade "$TMP/assembly.vdb" -o "$TMP/g.vdb" -q &&
$HOVOX layers "$TMP/g.vdb" -o "$TMP/stack" --dpi 50,50 --layer-height 1 &&
# the target is a mean of float fractions: its last digits follow the build's float contraction
# (the sanitizer build differs past the 8th), so it is shown to 7 decimals
sed -n '/"materials"/,/]/p' "$TMP/stack/manifest.json" | sed -E 's/("target": [0-9]+\.[0-9]{7})[0-9]*/\1/' &&
/usr/bin/python3 tests/cli/png_palette_map.py "$TMP/stack/layer-00005.png" '.AV?' --size
