$HOVOX export "$TMP/m.vdb" -o "$TMP/m.vti" --coarsen 2
