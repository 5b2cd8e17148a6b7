$HOVOX voxelize tests/data/good/tet_ascii.stl --voxel-size 0.1 --adjacency 6 -o "$TMP/t.vdb"
