# --bits is for .3mf
/usr/bin/python3 tests/cli/cases/export_model.py "$TMP/m.vdb" || exit 9
$HOVOX export "$TMP/m.vdb" -o "$TMP/m.vti" --bits 16
