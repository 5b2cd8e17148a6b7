$HOVOX info tests/data/bad/ply_truncated.ply
