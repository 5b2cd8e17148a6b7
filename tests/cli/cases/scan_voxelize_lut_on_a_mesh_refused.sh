# --lut and --icc are for scanned volumes; --icc without a colour table is refused too
printf 'HU,A\n0,1\n' > "$TMP/t.csv"
$HOVOX generate box min=0,0,0 max=4,4,2 -o "$TMP/a.stl" >/dev/null && $HOVOX voxelize "$TMP/a.stl" --dims 8 --lut "$TMP/t.csv" -o "$TMP/x.vdb"; echo "rc=$?"
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 8,8,8 --spacing 12,12,14 --formats nii || exit 9
$HOVOX voxelize "$TMP/ph/phantom.nii" --iso 0 --icc /usr/share/color/icc/ghostscript/default_cmyk.icc -o "$TMP/x.vdb"; rc=$?; ls "$TMP"; exit $rc
