# the exact syntax: two AGS groups (union), colours, then probe the result
$HOVOX generate box sx=10 sy=10 sz=10 -o "$TMP/b.stl" >/dev/null
$HOVOX voxelize "$TMP/b.stl" -o "$TMP/b.vdb" --dims 20 >/dev/null
$HOVOX grade "$TMP/b.vdb" -o "$TMP/g.vdb" --materials A,B,C --colors '#1f77b4,#ff7f0e,#2ca02c' \
    --frf axis:0,0,0:0,0,1 --ranges 0,10,0 --f 'sin(0.1538*d)' --ms 1,0,0 --me 0,1,0 \
    --frf plane:0,0,10:0,0,1 --ranges 0,5,0 --f d/dg --ms 0,0,1 --me 1,0,0 -q
echo "rc=$?"
$HOVOX probe "$TMP/g.vdb" 2,2,2 5,5,5 8,8,9
