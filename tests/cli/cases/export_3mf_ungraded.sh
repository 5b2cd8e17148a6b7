# a model without materials has nothing for a volumetric package: refused, nothing written
$HOVOX export tests/data/models/ungraded.vdb -o "$TMP/u.3mf"; rc=$?; ls -A "$TMP" | grep -v "^\.std"; exit $rc
