# issue 29: painting refused with one message and nothing written: a profile that is not ICC
# (exit 1), an RGB profile where the CMYK output profile is needed (exit 1), a missing profile
# (exit 4), a mesh without any colour (exit 1), --colour on a body that is not there (exit 1), a
# texture that is missing or not a picture (exit 1); usage errors (exit 2): --colour without
# BODY=, --icc without painting, colour options on a scanned volume
printf 'mtllib c.mtl\nv 0 0 0\nv 4 0 0\nv 0 4 0\nv 0 0 4\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl t\nf 1/1 3/3 2/2\nf 1/1 2/2 4/3\nf 1/1 4/3 3/2\nf 2/1 3/2 4/3\n' > "$TMP/c.obj"
printf 'newmtl t\nKd 1 0 0\n' > "$TMP/c.mtl"
printf 'not a profile' > "$TMP/x.icc"
$HOVOX voxelize "$TMP/c.obj" --voxel-size 0.5 --colour-depth 1 --icc "$TMP/x.icc" -o "$TMP/a.vdb"
echo "rc=$?"
$HOVOX voxelize "$TMP/c.obj" --voxel-size 0.5 --colour-depth 1 --icc /usr/share/color/icc/ghostscript/srgb.icc -o "$TMP/a.vdb"
echo "rc=$?"
$HOVOX voxelize "$TMP/c.obj" --voxel-size 0.5 --colour-depth 1 --icc "$TMP/none.icc" -o "$TMP/a.vdb"
echo "rc=$?"
printf 'v 0 0 0\nv 4 0 0\nv 0 4 0\nv 0 0 4\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' > "$TMP/plain.obj"
$HOVOX voxelize "$TMP/plain.obj" --voxel-size 0.5 --colour-depth 1 -o "$TMP/a.vdb"
echo "rc=$?"
$HOVOX voxelize "$TMP/plain.obj" --voxel-size 0.5 --colour hub=#ff0000 -o "$TMP/a.vdb"
echo "rc=$?"
printf 'newmtl t\nmap_Kd skin.png\n' > "$TMP/c.mtl"
$HOVOX voxelize "$TMP/c.obj" --voxel-size 0.5 --colour-depth 1 -o "$TMP/a.vdb"
echo "rc=$?"
printf 'not a picture' > "$TMP/skin.png"
$HOVOX voxelize "$TMP/c.obj" --voxel-size 0.5 --colour-depth 1 -o "$TMP/a.vdb"
echo "rc=$?"
$HOVOX voxelize "$TMP/plain.obj" --voxel-size 0.5 --colour '#ff0000' -o "$TMP/a.vdb"
echo "rc=$?"
$HOVOX voxelize "$TMP/plain.obj" --voxel-size 0.5 --icc "$TMP/x.icc" -o "$TMP/a.vdb"
echo "rc=$?"
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 8,8,8 --spacing 12,12,14 --formats nii >/dev/null || exit 9
$HOVOX voxelize "$TMP/ph/phantom.nii" --iso 0 --colour-depth 1 -o "$TMP/a.vdb"
echo "rc=$?"
rm -r "$TMP/ph"
ls "$TMP"
