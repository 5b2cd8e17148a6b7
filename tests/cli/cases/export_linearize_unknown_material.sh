/usr/bin/python3 tests/cli/cases/export_model.py "$TMP/m.vdb" || exit 9
printf "fraction.glass,youngs_modulus\n0,1\n1,2\n" >"$TMP/e.csv"
$HOVOX export "$TMP/m.vdb" -o "$TMP/m.vti" --linearize youngs_modulus="$TMP/e.csv"; rc=$?; ls -A "$TMP" | grep -v "^\.std"; exit $rc
