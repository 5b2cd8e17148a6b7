$HOVOX profile tests/data/models/gap3.vdb tests/data/models/linear2.vdb --from 0,0,0 --to 1,2,3 -o "$TMP/p.csv"
