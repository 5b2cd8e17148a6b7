$HOVOX info tests/data/bad/ply_nan_vertex.ply
