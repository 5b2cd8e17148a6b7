$HOVOX generate box sx=4 sy=4 sz=4 -o "$TMP/b.stl" && mkdir "$TMP/stack" && echo keep >"$TMP/stack/notes.txt" &&
$HOVOX layers --mesh "$TMP/b.stl" -o "$TMP/stack" --mode mask --dpi 50,50 --layer-height 1 --force
echo "rc=$?"; ls -a "$TMP/stack"; echo "temporary: $(ls -a "$TMP" | grep -c tmp)"
