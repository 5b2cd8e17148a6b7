# a scanned volume as a tray part (issue 30 item 1): `--part SCAN@X,Y` with its shape and lookup table after it,
# beside a mesh part; the scan is printed from its data on the plate, and its pixels are exactly those of
# `layers SCAN --place X,Y` (tests/io/scan/tray_vs_layers.py, pixel-exact); the same part from a job file (keys
# scan, iso, lut; labels as a list) gives the same bytes; a clean-up (keep_largest) makes its model first; the
# quarter turn and copies move its affine; refusals name the part; over --max-memory: exit 3, nothing written
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 20,24,18 --spacing 2,2,3 --formats nii >/dev/null || exit 9
cd "$TMP"
printf 'HU,VeroClear,Agilus30,VeroWhite\n-1000,1,0,0\n0,0,1,0\n300,0,1,0\n1000,0,0,1\n' > bone.csv
"$HOVOX" generate box max=12,8,10 -o b.stl >/dev/null
R="--resin Agilus30=Agilus30Clear --resin VeroWhite=VeroPureWhite"
"$HOVOX" tray -o stack --part ph/phantom.nii@60,60 --iso -480 --lut bone.csv --part b.stl:VeroPureWhite@150,60 $R \
    --layers 800:804 --threads 2; echo "rc=$?"
"$HOVOX" layers ph/phantom.nii --iso -480 --mode mask --profile j750 --place 60,60 --layers 800:804 -o lay -q >/dev/null
/usr/bin/python3 - <<'PY'
import json
m = json.load(open("stack/manifest.json"))
for p in m["parts"]:
    print(p["name"], p["mesh"], p["scan"] if "scan" in p else "-", p["at_mm"], p["image_px"], sorted(p["materials"]))
PY
/usr/bin/python3 "$OLDPWD/tests/io/scan/tray_vs_layers.py" stack lay; echo "rc=$?"
mkdir jobs && cat >jobs/job.json <<'JSON'
{"schema": 1, "resin": {"Agilus30": "Agilus30Clear", "VeroWhite": "VeroPureWhite"},
 "parts": [{"scan": "../ph/phantom.nii", "iso": -480, "lut": "../bone.csv", "at": [60, 60]},
           {"mesh": "../b.stl", "material": "VeroPureWhite", "at": [150, 60]}]}
JSON
"$HOVOX" tray jobs/job.json -o stack2 --layers 800:804 -q >/dev/null; echo "rc=$?"
for i in 800 801 802 803; do cmp -s stack/layer-00$i.png stack2/layer-00$i.png && echo "layer $i same"; done
cat >jobs/labels.json <<'JSON'
{"schema": 1, "parts": [{"scan": "../ph/phantom.nii", "labels": [1000, 30], "material": "VeroPureWhite", "at": [60, 60]}]}
JSON
"$HOVOX" tray jobs/labels.json --dry-run | grep "^part"; echo "rc=$?"
"$HOVOX" tray -o s3 --part ph/phantom.nii@60,60,90x2 --iso -480 --keep-largest --lut bone.csv $R --dry-run | grep "^part"
echo "rc=$?"
# refusals
"$HOVOX" tray -o s3 --part ph/phantom.nii@60,60 --iso -480 --dry-run; echo "rc=$?"
"$HOVOX" tray -o s3 --part ph/phantom.nii:VeroPureWhite@60,60 --iso 1 --range 1,2 --dry-run; echo "rc=$?"
"$HOVOX" tray -o s3 --part b.stl:VeroPureWhite@60,60 --iso 1 --dry-run; echo "rc=$?"
"$HOVOX" tray -o s3 --part ph/phantom.nii:VeroPureWhite@60,60 --labels 1,x --dry-run; echo "rc=$?"
"$HOVOX" tray -o s3 --part ph/phantom.nii:VeroPureWhite@60,60 --iso 5000 --dry-run; echo "rc=$?"
"$HOVOX" tray -o s3 --part ph/phantom.nii:VeroPureWhite@60,60 --iso -480 --stl x.stl --dry-run; echo "rc=$?"
printf '{"schema": 1, "parts": [{"scan": "../ph/phantom.nii", "labels": [1, 2.5], "material": "A", "at": [60, 60]}]}' >jobs/bad.json
"$HOVOX" tray jobs/bad.json --dry-run; echo "rc=$?"
"$HOVOX" tray -o s4 --part ph/phantom.nii@60,60 --iso -480 --lut bone.csv $R --threads 2 --max-memory 25M; rc=$?
ls | grep -c s4; exit $rc
