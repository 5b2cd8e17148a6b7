/usr/bin/python3 tests/cli/cases/export_model.py "$TMP/m.vdb" || exit 9
$HOVOX export "$TMP/m.vdb" -o "$TMP/m.vti" --max-memory 64K --box -5,-5,-5,15,15,15; rc=$?; ls -A "$TMP" | grep -v "^\.std"; exit $rc
