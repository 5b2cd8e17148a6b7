$HOVOX info tests/data/bad/ascii_nan.stl
