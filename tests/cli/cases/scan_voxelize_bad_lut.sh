# a lookup table whose values do not rise: one message with the file and the line, exit 1, nothing written
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 8,8,8 --spacing 12,12,14 --formats nii || exit 9
printf 'HU,Soft,Hard\n-1000,1,0\n300,0.5,0.5\n# a comment\n300,0,1\n' > "$TMP/bad.csv"
$HOVOX voxelize "$TMP/ph/phantom.nii" --iso 0 --lut "$TMP/bad.csv" -o "$TMP/x.vdb"; rc=$?; ls "$TMP"; exit $rc
