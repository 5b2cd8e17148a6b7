$HOVOX profile tests/data/models/ungraded.vdb --from 0,0,0 --to 7,7,7 -o "$TMP/p.csv" --plot "$TMP/p.png"; rc=$?; ls "$TMP"; exit $rc
