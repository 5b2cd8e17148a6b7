$HOVOX contours tests/data/good/tet_ascii.stl --layer-height -0.1 -o "$TMP/x.cli"
