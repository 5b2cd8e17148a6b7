$HOVOX export "$TMP/m.vdb"
