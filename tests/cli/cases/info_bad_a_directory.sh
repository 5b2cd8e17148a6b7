$HOVOX info tests/data/bad/a_directory.stl
