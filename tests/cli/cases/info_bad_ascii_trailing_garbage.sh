$HOVOX info tests/data/bad/ascii_trailing_garbage.stl
