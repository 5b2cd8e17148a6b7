$HOVOX contours tests/data/good/tet_ascii.stl -o "$TMP/x.cli"
