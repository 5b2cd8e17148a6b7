$HOVOX info tests/data/bad/ascii_no_facets.stl
