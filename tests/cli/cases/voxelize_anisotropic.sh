$HOVOX generate box sx=20 sy=20 sz=20 -o "$TMP/box.stl" && $HOVOX voxelize "$TMP/box.stl" --dims 64,64,45 -o "$TMP/box.vdb"
