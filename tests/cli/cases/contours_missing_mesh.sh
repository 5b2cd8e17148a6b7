$HOVOX contours "$TMP/nothing.stl" --layer-height 0.1 -o "$TMP/x.cli"
