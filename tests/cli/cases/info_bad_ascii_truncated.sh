$HOVOX info tests/data/bad/ascii_truncated.stl
