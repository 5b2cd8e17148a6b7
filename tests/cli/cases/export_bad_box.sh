$HOVOX export "$TMP/m.vdb" -o "$TMP/m.vti" --box 0,0,0,1,1
