# a DICOM series with a slice of another size among its slices
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 20,24,18 --spacing 4,4,6 --formats dicom || exit 9
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/other" --size 22,24,18 --spacing 4,4,6 --formats dicom || exit 9
cp "$TMP/other/dicom/$(ls "$TMP/other/dicom" | head -n 1)" "$TMP/ph/dicom/zz_stranger.dcm"
$HOVOX info "$TMP/ph/dicom"
