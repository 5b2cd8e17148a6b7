$HOVOX info tests/data/bad/count_too_large.stl
