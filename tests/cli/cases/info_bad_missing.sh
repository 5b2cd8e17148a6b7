$HOVOX info tests/data/bad/no_such_file.stl
