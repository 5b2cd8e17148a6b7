$HOVOX probe "$TMP/none.vdb" 1,2,3
