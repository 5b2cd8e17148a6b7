# a flat (zero-height) open mesh has no layer: an empty but well-formed CLI file
$HOVOX contours tests/data/good/open_square.stl --layer-height 0.1 -o "$TMP/flat.cli" && cat "$TMP/flat.cli"
