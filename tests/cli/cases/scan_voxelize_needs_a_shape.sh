/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 8,8,8 --spacing 12,12,14 --formats nii || exit 9
$HOVOX voxelize "$TMP/ph/phantom.nii" -o "$TMP/x.vdb"; rc=$?; ls "$TMP"; exit $rc
