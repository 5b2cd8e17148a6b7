$HOVOX info tests/data/good/tet_ascii_upper_crlf.stl
