$HOVOX layers m.vdb --mesh tests/data/good/tet_ascii.stl -o "$TMP/stack" --mode fractions --gcvf "$TMP/x.zip"
