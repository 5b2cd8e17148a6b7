# a model without materials has nothing for a volumetric package: refused, nothing written; nor
# does this one (made before hovox recorded shapes) record a shape for the plain .3mf
$HOVOX export tests/data/models/ungraded.vdb -o "$TMP/u.3mf" --volumetric; echo "rc=$?"
$HOVOX export tests/data/models/ungraded.vdb -o "$TMP/u.3mf"; rc=$?; ls -A "$TMP" | grep -v "^\.std"; exit $rc
