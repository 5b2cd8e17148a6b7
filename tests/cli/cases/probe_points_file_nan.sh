printf "1,2,3\n4,5,nan\n" > "$TMP/p.csv"
$HOVOX probe tests/data/models/gap3.vdb --points "$TMP/p.csv"
