# issue 28: export .stl/.obj writes the shape the model records, not its voxels: a plain model
# gives its recorded mesh, placed, byte for byte as the source STL (bbox 0..40 x 0..20 x 0..10,
# every edge shared by two facets), the same bytes from Lua; a Boolean's surface is refused
# naming the model, nothing written; --box does not apply
cd "$TMP" || exit 1
$HOVOX generate box min=0,0,0 max=40,20,10 -o plate.stl >/dev/null &&
$HOVOX generate cylinder base=20,10,-1 axis=2 length=12 radius=5 segments=64 -o rod.stl >/dev/null &&
$HOVOX voxelize plate.stl --voxel-size 0.5 -o plate.vdb -q >/dev/null &&
$HOVOX voxelize rod.stl --voxel-size 0.5 -o rod.vdb -q >/dev/null &&
$HOVOX grade plate.vdb -o a.vdb --materials A,B --frf point:0,0,0 --ranges 0,0,0 --ms 1,0 --me 1,0 >/dev/null &&
$HOVOX grade rod.vdb -o b.vdb --materials A,B --frf point:0,0,0 --ranges 0,0,0 --ms 0,1 --me 0,1 >/dev/null &&
$HOVOX boolean a.vdb subtract b.vdb -o holed.vdb -q || exit 1
$HOVOX export a.vdb -o part.stl; echo "rc=$?"
cmp -s part.stl plate.stl && echo "part.stl: the recorded mesh byte for byte"
$HOVOX export a.vdb -o part.obj -q >/dev/null; echo "rc=$?"
$HOVOX info part.obj | grep -E "^(facets|bbox|volume|open edges|non-manifold|closed)"
echo 'hovox.load("a.vdb"):export{path = "lua.stl"}' > e.lua && $HOVOX run e.lua && cmp part.stl lua.stl && echo "Lua: the same bytes"
$HOVOX export holed.vdb -o holed.stl; echo "rc=$?"
ls holed.stl 2>&1 | sed 's/.*: //'
$HOVOX export a.vdb -o part.stl --box 0,0,0,1,1,1; echo "rc=$?"
