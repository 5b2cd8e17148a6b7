$HOVOX info tests/data/good/tet_one_flipped.stl
