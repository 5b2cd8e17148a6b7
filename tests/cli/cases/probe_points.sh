# linear2: rigid = (x - 1) / 7.5 inside x in [1, 8.5] (voxels of 0.5 mm from x = 1);
# 8.8 is 0.6 voxel beyond the last centre: occupancy 0.4, outside, fractions of the boundary;
# (-1,0,0) is far outside: all 0. Negative coordinates are points, not options.
$HOVOX probe tests/data/models/linear2.vdb 1,2,3 4.75,5.75,6.75 8.5,9.5,10.5 2.875,4,5 8.8,5,6 -1,0,0
