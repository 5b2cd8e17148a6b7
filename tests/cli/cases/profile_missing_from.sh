$HOVOX profile tests/data/models/gap3.vdb --to 1,2,3 -o "$TMP/p.csv"
