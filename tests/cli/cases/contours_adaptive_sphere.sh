$HOVOX generate sphere radius=10 -o "$TMP/s.stl" &&
$HOVOX contours "$TMP/s.stl" --adaptive 0.25,2 -o "$TMP/s.cli" && grep -c '^\$\$LAYER/' "$TMP/s.cli"
