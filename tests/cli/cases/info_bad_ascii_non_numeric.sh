$HOVOX info tests/data/bad/ascii_non_numeric.stl
