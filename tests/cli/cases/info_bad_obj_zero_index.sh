$HOVOX info tests/data/bad/obj_zero_index.obj
