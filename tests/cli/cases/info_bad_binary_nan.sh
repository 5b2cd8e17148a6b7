$HOVOX info tests/data/bad/binary_nan.stl
