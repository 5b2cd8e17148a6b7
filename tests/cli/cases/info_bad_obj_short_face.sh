$HOVOX info tests/data/bad/obj_short_face.obj
