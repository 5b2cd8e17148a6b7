$HOVOX export "$TMP/m.vdb" -o "$TMP/m.vti" --linearize e.csv
