# issue 27 item 2: a mesh goes to a stack in one step, each body in its material. The one-step
# stack of core_in_shell.3mf (a Vero shell, its Agilus core) is byte for byte the stack of
# voxelize, grade (no sources) and layers --mesh at the same voxel size; an OBJ of two boxes
# without materials gets them from --material (left VeroCyan, right Agilus30: palette 1 left of
# palette 2); a composite body prints its mixture as fractions; a body without a material is
# refused naming it and the option (exit 1, nothing written); --material on a model is a usage
# error (exit 2).
m=tests/data/good/core_in_shell.3mf
$HOVOX voxelize $m -o "$TMP/a.vdb" --voxel-size 0.5 >/dev/null &&
$HOVOX grade "$TMP/a.vdb" -o "$TMP/g.vdb" -q &&
$HOVOX layers "$TMP/g.vdb" --mesh $m -o "$TMP/three" --dpi 50,50 --layer-height 1 -q >/dev/null &&
$HOVOX layers $m -o "$TMP/one" --dpi 50,50 --layer-height 1 --voxel-size 0.5 &&
for f in "$TMP"/three/*.png; do cmp "$f" "$TMP/one/$(basename "$f")" || exit 1; done && echo "one step = three steps"
echo "rc=$?"
{
    for z in 0 4; do for y in 0 4; do for x in 0 4 8; do echo "v $x $y $z"; done; done; done
    echo "o left"
    echo "f 1 4 5
f 1 5 2
f 7 8 11
f 7 11 10
f 1 2 8
f 1 8 7
f 2 5 11
f 2 11 8
f 5 4 10
f 5 10 11
f 4 1 7
f 4 7 10"
    echo "o right"
    echo "f 2 5 6
f 2 6 3
f 8 9 12
f 8 12 11
f 2 3 9
f 2 9 8
f 3 6 12
f 3 12 9
f 6 5 11
f 6 11 12
f 5 2 8
f 5 8 11"
} >"$TMP/two.obj"
$HOVOX layers "$TMP/two.obj" -o "$TMP/two" --dpi 12.7,12.7 --layer-height 1 --material left=VeroCyan \
    --material right=Agilus30 --voxel-size 0.5 | grep -v '^memory' &&
/usr/bin/python3 tests/cli/png_palette_map.py "$TMP/two/layer-00002.png" '.CA'
echo "rc=$?"
$HOVOX layers tests/data/good/composite_core.3mf -o "$TMP/mix" --dpi 25.4,25.4 --layer-height 1 --mode fractions |
    sed -n '/^material/,$p'
echo "rc=$?"
$HOVOX layers "$TMP/two.obj" -o "$TMP/none" --dpi 50,50 --layer-height 1 --material left=VeroCyan
echo "rc=$?"
$HOVOX layers "$TMP/g.vdb" -o "$TMP/none" --material core=VeroCyan
echo "rc=$?"
ls "$TMP"
