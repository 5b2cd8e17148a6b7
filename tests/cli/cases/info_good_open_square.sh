$HOVOX info tests/data/good/open_square.stl
