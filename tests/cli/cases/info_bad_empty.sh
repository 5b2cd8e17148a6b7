$HOVOX info tests/data/bad/empty.stl
