$HOVOX render "$TMP/nothing.vdb" -o "$TMP/out.png"; echo "rc=$?"; ls "$TMP"
