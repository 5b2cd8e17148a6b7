/usr/bin/python3 tests/cli/cases/export_model.py "$TMP/m.vdb" || exit 9
$HOVOX export "$TMP/m.vdb" -o "$TMP/m.vti" --box 0.1,0.1,0.1,0.2,0.2,0.2
