$HOVOX generate box sx=10 sy=10 sz=10 -o "$TMP/b.stl" &&
$HOVOX contours "$TMP/b.stl" --layer-height 2.5 --per-layer "$TMP/layers" -q && ls "$TMP/layers" &&
xmllint --noout "$TMP"/layers/*.svg
