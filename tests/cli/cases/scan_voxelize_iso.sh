# a model from a DICOM series, no mesh: the skin's iso value (halfway between air and skin), 1 mm voxels
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 40,48,36 --spacing 2,2,3 --formats dicom || exit 9
$HOVOX voxelize "$TMP/ph/dicom" --iso -480 --voxel-size 1 -o "$TMP/head.vdb" && ls "$TMP"
