# a flat (zero-height) open mesh has no layer: one clear message, exit 1, no output file
$HOVOX contours tests/data/good/open_square.stl --layer-height 0.1 -o "$TMP/flat.cli"
echo "rc=$?; files: $(ls "$TMP" | wc -l)"
