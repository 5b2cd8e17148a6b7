$HOVOX generate box sx=10 sy=10 sz=10 -o "$TMP/b.stl" &&
$HOVOX contours "$TMP/b.stl" --layer-height 2.5 --per-layer "$TMP/layers" && ls "$TMP/layers" &&
xmllint --noout "$TMP"/layers/*.svg
# a second run replaces the directory whole: no stale layers from the first run
$HOVOX contours "$TMP/b.stl" --layer-height 5 --per-layer "$TMP/layers" && ls "$TMP/layers"
# a directory holding anything else is not replaced
touch "$TMP/layers/notes.txt"
$HOVOX contours "$TMP/b.stl" --layer-height 5 --per-layer "$TMP/layers"
echo "rc=$?"; ls "$TMP/layers"; echo "temporary: $(ls -a "$TMP" | grep -c '\.layers\.')"
