$HOVOX probe tests/data/good/tet_ascii.stl 1,2,3
