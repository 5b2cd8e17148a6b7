$HOVOX info tests/data/bad/header_only_count5.stl
