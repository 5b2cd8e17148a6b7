$HOVOX profile tests/data/models/gap3.vdb --from 0,0,0 --to 1,2,3 -o "$TMP/p.csv" --plot "$TMP/p.png" --title "$(printf "bad \377 title")"; rc=$?; ls "$TMP"; exit $rc
