# linear2 along x through voxel centres: t = x - 1, rigid = t / 7.5 exactly
$HOVOX profile tests/data/models/linear2.vdb --from 1,4.5,6.5 --to 8.5,4.5,6.5 --samples 16 -o "$TMP/p.csv" && cat "$TMP/p.csv" && ls "$TMP"
