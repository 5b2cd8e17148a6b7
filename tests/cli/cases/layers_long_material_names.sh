# The target/achieved table is as wide as the longest material name (issue 32 item 19: long
# names pushed their row's numbers out of the columns).
cd "$TMP"
"$HOVOX" generate box max=4,4,0.2 -o b.stl >/dev/null
"$HOVOX" voxelize b.stl --voxel-size 0.25 -o o.vdb -q >/dev/null
"$HOVOX" grade o.vdb -o g.vdb --materials A,Agilus30Clear_support_blend --frf plane:0,0,0:1,0,0 --ranges 0,4,0 \
    --ms 1,0 --me 0,1 -q
"$HOVOX" layers g.vdb --mesh b.stl -o h --dpi 100,100 --layer-height 0.1 | sed -n '/^material/,/^wrote/p'
"$HOVOX" layers g.vdb --mesh b.stl -o f --dpi 100,100 --layer-height 0.1 --mode fractions | sed -n '/^material/,/^wrote/p'
