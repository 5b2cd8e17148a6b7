$HOVOX export "$TMP/m.vdb" -o "$TMP/m.vti" --properties hashin
