# layers without its input: --mesh alone (not --mode mask), and nothing at all; exit 2 naming what it takes
$HOVOX layers --mesh tests/data/good/tet_ascii.stl -o "$TMP/stack"; echo "rc=$?"
$HOVOX layers -o "$TMP/stack"; echo "rc=$?"
