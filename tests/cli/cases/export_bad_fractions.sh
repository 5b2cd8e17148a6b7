/usr/bin/python3 tests/cli/cases/export_model.py "$TMP/m.vdb" --bad || exit 9
$HOVOX export "$TMP/m.vdb" -o "$TMP/m.vtu"; rc=$?; ls -A "$TMP" | grep -v "^\.std"; exit $rc
