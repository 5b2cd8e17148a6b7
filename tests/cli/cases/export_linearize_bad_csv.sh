printf "fraction.b,youngs_modulus\n0,1\n0.7,2\n0.6,3\n" >"$TMP/e.csv"
$HOVOX export tests/data/none.vdb -o "$TMP/m.vti" --linearize youngs_modulus="$TMP/e.csv"
