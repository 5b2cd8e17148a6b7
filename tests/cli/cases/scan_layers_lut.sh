# direct printing of a scan (issue 30 item 4): the phantom's skin iso-surface evaluated at every pixel, materials from
# the Hounsfield lookup table, halftoned; the manifest names the table's materials
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 40,48,36 --spacing 2,2,3 --formats nii || exit 9
printf 'HU,VeroClear,Agilus30,VeroWhite\n-1000,1,0,0\n0,0,1,0\n300,0,1,0\n1000,0,0,1\n' > "$TMP/bone.csv"
$HOVOX layers "$TMP/ph/phantom.nii" --iso -480 --lut "$TMP/bone.csv" --dpi 100,100 --layer-height 1 -o "$TMP/stack" || exit $?
/usr/bin/python3 -c 'import json,sys; m=json.load(open(sys.argv[1])); print([x["name"] for x in m["materials"]], m["layers_total"], m["width"], m["height"])' "$TMP/stack/manifest.json"
