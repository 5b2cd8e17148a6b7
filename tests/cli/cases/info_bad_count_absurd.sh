$HOVOX info tests/data/bad/count_absurd.stl
