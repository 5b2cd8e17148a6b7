# a directory with a stranger among the slices
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 20,24,18 --spacing 4,4,6 --formats dicom || exit 9
echo "notes" > "$TMP/ph/dicom/README.txt"
$HOVOX info "$TMP/ph/dicom"
