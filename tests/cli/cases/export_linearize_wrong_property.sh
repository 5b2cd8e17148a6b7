printf "fraction.b,density\n0,1\n1,2\n" >"$TMP/e.csv"
$HOVOX export tests/data/none.vdb -o "$TMP/m.vti" --linearize youngs_modulus="$TMP/e.csv"
