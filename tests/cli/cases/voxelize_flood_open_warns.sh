$HOVOX voxelize tests/data/good/open_square.stl --fill flood --dims 8 -o "$TMP/o.vdb" -q >/dev/null; echo "rc=$?"
