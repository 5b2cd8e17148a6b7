# gap3 from x = -3 to 27 in steps of 2.5: outside, block 1, gap, block 2, outside
$HOVOX profile tests/data/models/gap3.vdb --from=-3,3.5,3.5 --to=27,3.5,3.5 --samples 13 -o -
