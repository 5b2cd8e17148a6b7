$HOVOX generate sphere radus=3 -o "$TMP/s.stl"
