$HOVOX info tests/data/bad/obj_forward_reference.obj
