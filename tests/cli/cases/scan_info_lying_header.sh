# a NRRD header whose sizes say more than the file holds
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 20,24,18 --spacing 4,4,6 --formats nrrd.raw || exit 9
sed 's/^sizes: 20 24 18/sizes: 20 24 180/' "$TMP/ph/phantom_raw.nrrd" > "$TMP/lies.nrrd"
$HOVOX info "$TMP/lies.nrrd"
