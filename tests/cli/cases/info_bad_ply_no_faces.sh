$HOVOX info tests/data/bad/ply_no_faces.ply
