# the CSV cannot be written: the plot is not left behind either (no temporary files either)
$HOVOX profile tests/data/models/gap3.vdb --from 0,0,0 --to 23,7,7 -o /nonexistent-dir/p.csv --plot "$TMP/p.png"; rc=$?; ls -A "$TMP" | grep -v "^\.std"; exit $rc
