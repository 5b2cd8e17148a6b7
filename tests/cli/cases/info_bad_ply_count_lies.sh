$HOVOX info tests/data/bad/ply_count_lies.ply
