# ASCII CLI of a 20 mm cube: a 4 mm first layer (from $$DIMENSION's lowest z), then 8 mm layers;
# $$LAYERS counts the layers the summary counts (issue 32 item 19: it counted a zero layer more)
$HOVOX generate box sx=20 sy=20 sz=20 -o "$TMP/box.stl" &&
$HOVOX contours "$TMP/box.stl" --first-layer 4 --layer-height 8 -o "$TMP/box.cli" && cat "$TMP/box.cli"
