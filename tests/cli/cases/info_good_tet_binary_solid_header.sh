$HOVOX info tests/data/good/tet_binary_solid_header.stl
