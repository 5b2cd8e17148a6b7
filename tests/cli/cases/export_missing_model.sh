$HOVOX export "$TMP/none.vdb" -o "$TMP/m.vti"
