$HOVOX info tests/data/bad/ply_bad_index.ply
