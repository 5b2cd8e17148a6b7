$HOVOX contours tests/data/good/tet_ascii.stl --adaptive 0.3,0.1 -o "$TMP/x.cli"
