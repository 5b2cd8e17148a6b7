# --dry-run --bits 16: the plan (triangles known, vertices once welded), nothing written
/usr/bin/python3 tests/cli/cases/export_model.py "$TMP/m.vdb" || exit 9
$HOVOX export "$TMP/m.vdb" -o "$TMP/m.3mf" --volumetric --dry-run --bits 16 --properties none; rc=$?; ls -A "$TMP" | grep -v "^\.std"; exit $rc
