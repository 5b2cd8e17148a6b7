# a .nii.gz cut short: the message says how far the data goes
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 20,24,18 --spacing 4,4,6 --formats nii || exit 9
gzip -c "$TMP/ph/phantom.nii" | head -c 1500 > "$TMP/cut.nii.gz"
$HOVOX info "$TMP/cut.nii.gz"
