$HOVOX generate box sx=40 sy=40 sz=4 -o "$TMP/b.stl" &&
$HOVOX layers --mesh "$TMP/b.stl" -o "$TMP/stack" --mode mask --threads 2 --max-memory 1M
echo "rc=$?"; ls "$TMP"
