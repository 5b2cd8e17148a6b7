$HOVOX info tests/data/bad/binary_inf.stl
