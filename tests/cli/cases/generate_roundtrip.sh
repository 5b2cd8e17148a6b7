$HOVOX generate holed-box sx=40 sy=30 sz=20 hole=8 -o "$TMP/box.stl" && $HOVOX info "$TMP/box.stl"
