$HOVOX info tests/data/bad/obj_no_faces.obj
