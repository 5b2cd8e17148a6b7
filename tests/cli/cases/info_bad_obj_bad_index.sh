$HOVOX info tests/data/bad/obj_bad_index.obj
