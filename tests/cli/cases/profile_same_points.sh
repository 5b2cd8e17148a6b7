$HOVOX profile tests/data/models/gap3.vdb --from 1,2,3 --to 1,2,3 -o "$TMP/p.csv"
