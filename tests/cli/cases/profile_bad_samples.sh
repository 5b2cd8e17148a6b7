$HOVOX profile tests/data/models/gap3.vdb --from 0,0,0 --to 1,2,3 --samples 1 -o "$TMP/p.csv"
