$HOVOX layers model.vdb -o "$TMP/stack"
