# a scanned volume prints its materials from --lut (or its shape alone with --mode mask); --mesh is
# for models; scan options are refused for a model; over --max-memory: exit 3, nothing written
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 20,24,18 --spacing 4,4,6 --formats nii || exit 9
printf 'HU,A\n0,1\n' > "$TMP/t.csv"
$HOVOX layers "$TMP/ph/phantom.nii" --iso -480 -o "$TMP/a"; echo "rc=$?"
$HOVOX layers "$TMP/ph/phantom.nii" --iso -480 --lut "$TMP/t.csv" --mesh "$TMP/t.csv" -o "$TMP/a"; echo "rc=$?"
$HOVOX layers "$TMP/ph/phantom.nii" --lut "$TMP/t.csv" -o "$TMP/a"; echo "rc=$?"
$HOVOX layers "$TMP/m.vdb" --iso 3 -o "$TMP/a"; echo "rc=$?"
$HOVOX layers "$TMP/ph/phantom.nii" --iso -480 --lut "$TMP/t.csv" --max-memory 1M -o "$TMP/a"; rc=$?; ls "$TMP"; exit $rc
