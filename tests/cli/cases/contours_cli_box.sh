# ASCII CLI of a 20 mm cube: zero layer, a 4 mm first layer, then 8 mm layers
$HOVOX generate box sx=20 sy=20 sz=20 -o "$TMP/box.stl" &&
$HOVOX contours "$TMP/box.stl" --first-layer 4 --layer-height 8 -o "$TMP/box.cli" && cat "$TMP/box.cli"
