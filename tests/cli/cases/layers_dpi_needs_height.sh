$HOVOX layers --mesh tests/data/good/tet_ascii.stl -o "$TMP/stack" --mode mask --dpi 600,300
