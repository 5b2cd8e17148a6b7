$HOVOX generate gear height=5 -o "$TMP/g.stl" &&
$HOVOX layers --mesh "$TMP/g.stl" --mode mask --profile j850 --threads 2 --dry-run
