# materials from the phantom's Hounsfield units (README "Lookup tables"): brain and skin (30, 40 HU)
# soft, skull (1000 HU) hard; probed at the centre (brain), in the skull shell and in the skin
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 40,48,36 --spacing 2,2,3 --formats nii || exit 9
cat > "$TMP/bone.csv" <<'CSV'
# Hounsfield units to resins
HU,VeroClear,Agilus30,VeroWhite
-1000,1,0,0
0,0,1,0
300,0,1,0
1000,0,0,1
CSV
$HOVOX voxelize "$TMP/ph/phantom.nii" --iso -480 --voxel-size 2 --lut "$TMP/bone.csv" -o "$TMP/head.vdb" || exit $?
$HOVOX probe "$TMP/head.vdb" 2,-3,5 32.6,-3,5 36.2,-3,5 2,-3,53
