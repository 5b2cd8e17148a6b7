$HOVOX info tests/data/bad/3mf_nan_vertex.3mf
