$HOVOX info tests/data/bad/obj_nan_vertex.obj
