$HOVOX voxelize tests/data/good/open_square.stl --dims 8,8,8 -o "$TMP/o.vdb"
