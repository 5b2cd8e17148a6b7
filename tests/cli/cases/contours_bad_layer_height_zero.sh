$HOVOX contours tests/data/good/tet_ascii.stl --layer-height 0 -o "$TMP/x.cli"
