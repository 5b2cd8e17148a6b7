printf "x,y,z\n1,2,3\n1, abc ,2\n" > "$TMP/p.csv"
$HOVOX probe tests/data/models/gap3.vdb --points "$TMP/p.csv"
