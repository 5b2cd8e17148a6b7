$HOVOX info tests/data/bad/ascii_missing_endsolid.stl
