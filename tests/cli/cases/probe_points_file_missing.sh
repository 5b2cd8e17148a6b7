$HOVOX probe tests/data/models/gap3.vdb --points "$TMP/none.csv"
