$HOVOX info tests/data/bad/trailing_garbage.stl
