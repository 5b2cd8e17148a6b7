$HOVOX info tests/data/bad/ply_ascii_bad_value.ply
