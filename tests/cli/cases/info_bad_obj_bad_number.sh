$HOVOX info tests/data/bad/obj_bad_number.obj
