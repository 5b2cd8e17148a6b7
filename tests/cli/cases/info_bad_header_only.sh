$HOVOX info tests/data/bad/header_only.stl
