# issue 29: a UV-textured 3MF (texture2d group) and the same part as OBJ + MTL map_Kd + PNG, both
# written by Python, give the same fractions at every voxel within 0.01, the texture's ramp showing
# (tests/colour/check_textured.py); then UVs outside [0, 1] on a texture whose tile style is none:
# one message, exit 1, nothing written
/usr/bin/python3 tests/colour/check_textured.py $HOVOX "$TMP/a"
echo "rc=$?"
/usr/bin/python3 tests/colour/textured_cube.py "$TMP/b" --tile none --uv-scale 1.5
$HOVOX voxelize "$TMP/b/cube.3mf" --voxel-size 0.5 --colour-depth 1 -o "$TMP/b/x.vdb"
echo "rc=$?"
ls "$TMP/b"
