$HOVOX generate box sx=4 sy=4 sz=4 -o "$TMP/b.stl" &&
$HOVOX layers --mesh "$TMP/b.stl" -o "$TMP/stack" --mode mask --dpi 50,50 --layer-height 1 -q >/dev/null &&
$HOVOX layers --mesh "$TMP/b.stl" -o "$TMP/stack" --mode mask --dpi 50,50 --layer-height 2 -q >/dev/null
echo "rc=$?"
$HOVOX layers --mesh "$TMP/b.stl" -o "$TMP/stack" --mode mask --dpi 50,50 --layer-height 2 --force -q >/dev/null
echo "rc=$?"; ls "$TMP/stack"; echo "temporary: $(ls -a "$TMP" | grep -c '\.stack\.')"
