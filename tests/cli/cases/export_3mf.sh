# a graded model to a 3MF Volumetric package: the report, the package's parts, and hovox reading it
# back (probe: voxel centres, a fraction quantised to 8 bits: 0.363636 -> 93/255; the hole is outside)
/usr/bin/python3 tests/cli/cases/export_model.py "$TMP/m.vdb" || exit 9
out=$($HOVOX export "$TMP/m.vdb" -o "$TMP/m.3mf" --volumetric); rc=$?
printf "%s\n" "$out" | sed -E "s/\([0-9]+ bytes\)/(N bytes)/"
[ $rc = 0 ] || exit $rc
unzip -Z1 "$TMP/m.3mf" | sed -n '1,6p;$p'
echo "entries $(unzip -Z1 "$TMP/m.3mf" | wc -l)"
$HOVOX probe "$TMP/m.3mf" 3.5,0,0 2.5,1.5,0 0,0,0 5.5,2.5,1.5
