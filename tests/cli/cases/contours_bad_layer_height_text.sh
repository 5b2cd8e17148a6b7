$HOVOX contours tests/data/good/tet_ascii.stl --layer-height thin -o "$TMP/x.cli"
