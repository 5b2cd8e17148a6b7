/usr/bin/python3 tests/cli/cases/export_model.py "$TMP/m.vdb" || exit 9
$HOVOX export "$TMP/m.vdb" -o "$TMP/m.vti" --max-memory 1K; rc=$?; ls -A "$TMP" | grep -v "^\.std"; exit $rc
