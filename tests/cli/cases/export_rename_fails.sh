# the output name is taken by a directory: exit 4 and no partial or temporary file
/usr/bin/python3 tests/cli/cases/export_model.py "$TMP/m.vdb" || exit 9
mkdir "$TMP/m.vtu"
$HOVOX export "$TMP/m.vdb" -o "$TMP/m.vtu" -q; rc=$?; ls -A "$TMP" "$TMP/m.vtu" | grep -v "^\.std"; exit $rc
