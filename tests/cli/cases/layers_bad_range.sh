$HOVOX layers --mesh tests/data/good/tet_ascii.stl -o "$TMP/stack" --mode mask --layers 5:3
