# a composition that does not sum to 1, or an f that leaves [0, 1], is bad input (exit 1) with
# the offending value, and no output file is left
$HOVOX generate box sx=4 sy=4 sz=4 -o "$TMP/b.stl" >/dev/null
$HOVOX voxelize "$TMP/b.stl" -o "$TMP/b.vdb" --dims 8 >/dev/null
$HOVOX grade "$TMP/b.vdb" -o "$TMP/g1.vdb" --materials A,B --frf point:0,0,0 --ranges 0,4,0 --f d/dg --ms 0.6,0.6 --me 0,1
echo "rc=$?"
$HOVOX grade "$TMP/b.vdb" -o "$TMP/g2.vdb" --materials A,B --frf point:0,0,0 --ranges 0,9.54,0 --f '0.105*d' --ms 1,0 --me 0,1
echo "rc=$?"
$HOVOX grade "$TMP/b.vdb" -o "$TMP/g3.vdb" --materials A,B --frf point:0,0,0 --ranges 0,4,0 --f 'd/dg' --ms 1,0 --me -0.5,1.5
echo "rc=$?"
$HOVOX grade "$TMP/b.vdb" -o "$TMP/g4.vdb" --materials A,B --frf cone:0,0,0 --ranges 0,4,0 --f 'd/dg' --ms 1,0 --me 0,1
echo "rc=$?"; ls "$TMP"
# an option of a source given twice, or a list that does not parse, says so once (exit 2)
$HOVOX grade "$TMP/b.vdb" -o "$TMP/g5.vdb" --materials A,B --frf point:0,0,0 --ranges nan,4,0 --ms 1,0 --me 0,1
echo "rc=$?"
$HOVOX grade "$TMP/b.vdb" -o "$TMP/g6.vdb" --materials A,B --frf point:0,0,0 --ranges 0,4,0 --ms 1,0 --ms 0,1 --me 0,1
echo "rc=$?"
# a mask feature naming a grid the model lacks lists the bool grids it has (exit 1)
$HOVOX grade "$TMP/b.vdb" -o "$TMP/g7.vdb" --materials A,B --frf mask:core --ranges 0,4,0 --ms 1,0 --me 0,1
echo "rc=$?"
