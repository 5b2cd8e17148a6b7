$HOVOX generate box sx=10 sy=10 sz=10 -o "$TMP/b.stl" &&
$HOVOX contours "$TMP/b.stl" --layer-height 5 --binary -o "$TMP/b.cli" && sed -n '1,7p' "$TMP/b.cli" && wc -c < "$TMP/b.cli"
