$HOVOX generate box sx=4 sy=4 sz=4 -o "$TMP/b.stl" &&
$HOVOX layers --mesh "$TMP/b.stl" -o /nonexistent-dir/stack --mode mask --dpi 50,50 --layer-height 1
