$HOVOX generate sphere radius=-1 -o "$TMP/s.stl"; echo "rc=$?"; ls "$TMP"
