$HOVOX generate box sx=4 sy=4 sz=4 -o "$TMP/b.stl" &&
$HOVOX layers --mesh "$TMP/b.stl" -o "$TMP/stack" --mode mask --dpi 50,50 --layer-height 1 -q >/dev/null &&
$HOVOX layers --mesh "$TMP/b.stl" -o "$TMP/stack" --mode mask --dpi 50,50 --layer-height 2 -q >/dev/null
echo "rc=$?"
$HOVOX layers --mesh "$TMP/b.stl" -o "$TMP/stack" --mode mask --dpi 50,50 --layer-height 2 --force -q >/dev/null
echo "rc=$?"; ls "$TMP/stack"; echo "temporary: $(ls -a "$TMP" | grep -c '\.stack\.')"
# --force replaces a stack, never files hovox did not write
echo "my notes" >"$TMP/stack/notes.txt"
$HOVOX layers --mesh "$TMP/b.stl" -o "$TMP/stack" --mode mask --dpi 50,50 --layer-height 1 --force -q >/dev/null
echo "rc=$?"; ls "$TMP/stack"
# a killed job's hidden temporary is removed by the next job on the same directory
rm "$TMP/stack/notes.txt"; mkdir "$TMP/.stack.tmp-999999999"; touch "$TMP/.stack.tmp-999999999/layer-00000.png"
$HOVOX layers --mesh "$TMP/b.stl" -o "$TMP/stack" --mode mask --dpi 50,50 --layer-height 1 --force -q >/dev/null
echo "rc=$?; temporary: $(ls -a "$TMP" | grep -c '\.stack\.')"
