# a grid turned 30 degrees about z and 12 about x: the affine as the file says, in RAS
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --affine rotated --size 20,24,18 --spacing 4,4,6 --formats nii.gz,dicom || exit 9
$HOVOX info --json "$TMP/ph/phantom.nii.gz" "$TMP/ph/dicom" | /usr/bin/python3 -c '
import json, sys
for j in json.load(sys.stdin):
    print(j["format"], j["orientation"], " ".join("%.4f" % v for v in j["affine"]), j["dims"], j["unit"])'
