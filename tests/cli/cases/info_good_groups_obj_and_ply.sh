$HOVOX info tests/data/good/groups.obj tests/data/good/tet_binary_be.ply
