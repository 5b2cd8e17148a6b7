$HOVOX info tests/data/bad/ascii_inf.stl
