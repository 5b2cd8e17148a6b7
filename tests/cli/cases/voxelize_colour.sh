# issue 29: voxelize paints a part in its colours. The six-colour cube (OBJ + MTL Kd) painted 3 mm
# deep over an Agilus30 core against Pillow ImageCms (LittleCMS called independently): each face's
# skin within 0.01, the core one voxel past the depth, and the J750 blue-noise stack's 32^3 blocks
# within 0.02 (tests/colour/check_paint.py). Then the summary; --colour BODY=COLOUR on a file without
# colour (one body black, the other uncoloured: all core) with a core colour (mid grey, relative
# intent), probed in both bodies' skins and in the core.
/usr/bin/python3 tests/colour/check_paint.py $HOVOX "$TMP"
echo "rc=$?"
$HOVOX voxelize "$TMP/cube.obj" --voxel-size 0.5 --colour-depth 1.5 -o "$TMP/a.vdb"
echo "rc=$?"
cat >"$TMP/two.obj" <<'OBJ'
v 0 0 0
v 4 0 0
v 0 4 0
v 0 0 4
v 10 0 0
v 14 0 0
v 10 4 0
v 10 0 4
o left
f 1 3 2
f 1 2 4
f 1 4 3
f 2 3 4
o right
f 5 7 6
f 5 6 8
f 5 8 7
f 6 7 8
OBJ
$HOVOX voxelize "$TMP/two.obj" --voxel-size 0.25 --colour left=#000000 --colour-depth 0.5 --core '#808080' --intent relative -o "$TMP/b.vdb" --json
echo "rc=$?"
$HOVOX probe "$TMP/b.vdb" 0.875,0.875,0.125 10.875,0.875,0.125 0.875,0.875,0.875
$HOVOX colour '#808080' '#000000' --intent relative
