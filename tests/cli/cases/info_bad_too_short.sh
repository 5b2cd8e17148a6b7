$HOVOX info tests/data/bad/too_short.stl
