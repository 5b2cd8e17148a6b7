# hovox boolean refuses, with one message naming the model and the operation and writing
# nothing: an unknown operation (usage), a model without materials, models on different
# lattices, a damaged recorded shape
cd "$TMP" || exit 1
$HOVOX generate box min=0,0,0 max=4,4,2 -o a.stl >/dev/null && $HOVOX voxelize a.stl --voxel-size 0.5 -o a.vdb -q >/dev/null &&
$HOVOX voxelize a.stl --voxel-size 0.4 -o c.vdb -q >/dev/null &&
$HOVOX grade a.vdb -o ag.vdb --materials A,B --frf point:0,0,0 --ranges 0,0,0 --ms 1,0 --me 1,0 >/dev/null &&
$HOVOX grade c.vdb -o cg.vdb --materials A,B --frf point:0,0,0 --ranges 0,0,0 --ms 1,0 --me 1,0 >/dev/null || exit 1
$HOVOX boolean ag.vdb xor ag.vdb -o x.vdb; echo "rc=$?"
$HOVOX boolean ag.vdb union a.vdb -o x.vdb; echo "rc=$?"
$HOVOX boolean ag.vdb union cg.vdb -o x.vdb; echo "rc=$?"
/usr/bin/python3 -c "
import pyopenvdb as vdb
g, meta = vdb.readAll('ag.vdb')
key = [k for k in meta if k.startswith('hovox.geometry.leaf.')][0]
meta[key] = meta[key][:-8] + 'AAAAAAA='
vdb.write('damaged.vdb', grids=g, metadata=meta)
"
$HOVOX boolean damaged.vdb union ag.vdb -o x.vdb; echo "rc=$?"
ls x.vdb 2>&1 | sed 's/.*: //'
