# the skull (iso 520) with its cavity filled: one cavity, the ellipsoid scaled by 0.9 (241847 mm^3)
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 40,48,36 --spacing 2,2,3 --formats nii.gz || exit 9
$HOVOX voxelize "$TMP/ph/phantom.nii.gz" --iso 520 --fill-holes --keep-largest --voxel-size 1 --json -o "$TMP/skull.vdb"
