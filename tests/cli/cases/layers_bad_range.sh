# a range that does not parse is a usage error (exit 2); one past the plan's layers names the
# input, the range and the plan's (exit 1, nothing written)
$HOVOX layers --mesh tests/data/good/tet_ascii.stl -o "$TMP/stack" --mode mask --layers 5:3; echo "rc=$?"
$HOVOX layers --mesh tests/data/good/tet_ascii.stl -o "$TMP/stack" --mode mask --layers 1000:1002; echo "rc=$?"
ls "$TMP"
