$HOVOX info tests/data/good/tet_ascii.stl
