# a voxelized assembly (an Agilus core in a Vero shell, made by a Lua script) grades to its
# bodies' materials with no source; --region restricts a source to one body; refusals: an unknown
# region (exit 1, listing the regions), --region after its --frf (exit 2), a material list that
# does not name a body's material (exit 1), --region on a model without regions (exit 1), no
# --materials for a plain model (exit 2)
$HOVOX run tests/lua/scripts/assembly.lua "$TMP" &&
$HOVOX grade "$TMP/assembly.vdb" -o "$TMP/g.vdb" &&
$HOVOX probe "$TMP/g.vdb" 5,5,5 6.25,5.25,5.25 1,1,1 &&
$HOVOX grade "$TMP/assembly.vdb" -o "$TMP/r.vdb" --region core --frf point:5,5,5 --ranges 0,2,0 --ms 0,1 --me 1,0 &&
$HOVOX probe "$TMP/r.vdb" 5.25,5.25,5.25 6.25,5.25,5.25 1,1,1 &&
$HOVOX grade "$TMP/assembly.vdb" -o "$TMP/l.vdb" --materials Vero,Agilus,Support -q &&
$HOVOX probe "$TMP/l.vdb" 5,5,5 1,1,1
echo "rc=$?"
$HOVOX grade "$TMP/assembly.vdb" -o "$TMP/x.vdb" --region mantle --frf point:5,5,5 --ranges 0,2,0 --ms 0,1 --me 1,0
echo "rc=$?"
$HOVOX grade "$TMP/assembly.vdb" -o "$TMP/x.vdb" --frf point:5,5,5 --ranges 0,2,0 --ms 0,1 --me 1,0 --region core
echo "rc=$?"
$HOVOX grade "$TMP/assembly.vdb" -o "$TMP/x.vdb" --materials Vero,Rubber
echo "rc=$?"
$HOVOX run tests/lua/scripts/assembly.lua "$TMP" shell-first &&
$HOVOX grade "$TMP/assembly.vdb" -o "$TMP/x.vdb" --region core --frf point:5,5,5 --ranges 0,2,0 --ms 0,1 --me 1,0
echo "rc=$?"
$HOVOX voxelize "$TMP/assembly.stl" -o "$TMP/plain.vdb" --voxel-size 1 -q >/dev/null &&
$HOVOX grade "$TMP/plain.vdb" -o "$TMP/x.vdb" --materials A,B --region core --frf point:5,5,5 --ranges 0,2,0 --ms 0,1 --me 1,0
echo "rc=$?"
$HOVOX grade "$TMP/plain.vdb" -o "$TMP/x.vdb"
echo "rc=$?"
ls "$TMP"
