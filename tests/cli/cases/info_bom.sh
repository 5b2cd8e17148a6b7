# an ASCII STL saved with a UTF-8 byte order mark reads like any other
$HOVOX info tests/data/good/bom_ascii.stl
