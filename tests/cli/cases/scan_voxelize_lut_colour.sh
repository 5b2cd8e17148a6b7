# a colour lookup table: each voxel's interpolated colour as the six colour resins' fractions
# through the default output profile; the centre (30 HU) is the skin-pink row's colour, as hovox colour
# gives it (the model stores fractions as half floats: equal to about 1e-4)
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 20,24,18 --spacing 4,4,6 --formats nii || exit 9
printf 'HU,colour\n-1000,#ffffff00\n30,#d08070\n1000,#f0f0e0\n' > "$TMP/col.csv"
$HOVOX voxelize "$TMP/ph/phantom.nii" --iso -480 --voxel-size 2 --lut "$TMP/col.csv" --json -o "$TMP/head.vdb" || exit $?
$HOVOX probe "$TMP/head.vdb" 2,-3,5
$HOVOX colour '#d08070' --json | /usr/bin/python3 -c 'import json,sys; d=json.load(sys.stdin); print(",".join("%.6g" % f for f in d["colours"][0]["fractions"]))'
