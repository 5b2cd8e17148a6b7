# issue 28: hovox boolean gives the model Lua's Booleans give (every byte but the .vdb header's
# random UUID, the first 58 bytes), for each operation; the result records both meshes and the op
cd "$TMP" || exit 1
$HOVOX generate box min=0,0,0 max=20,10,2 -o plate.stl >/dev/null &&
$HOVOX generate cylinder base=10,5,-1 axis=2 length=4 radius=3 segments=64 -o rod.stl >/dev/null &&
$HOVOX voxelize plate.stl --voxel-size 0.5 -o plate.vdb -q >/dev/null &&
$HOVOX voxelize rod.stl --voxel-size 0.5 -o rod.vdb -q >/dev/null &&
$HOVOX grade plate.vdb -o red.vdb --materials A,B --frf plane:0,0,0:0,0,1 --ranges 0,0,0 --ms 1,0 --me 1,0 >/dev/null &&
$HOVOX grade rod.vdb -o blue.vdb --materials A,B --frf plane:0,0,0:0,0,1 --ranges 0,0,0 --ms 0,1 --me 0,1 >/dev/null &&
cat > ops.lua <<'LUA'
local mats = hovox.materials{{name = "A"}, {name = "B"}}
local function graded(path, ms)
  local o = hovox.object(hovox.voxelize(hovox.load_mesh(path), {voxel_size = 0.5}), mats)
  o:add_ags{feature = hovox.plane{point = {0, 0, 0}, normal = {0, 0, 1}}, d_neg = 0, d_grad = 0, d_pos = 0, ms = ms, me = ms}
  return o
end
for _, op in ipairs{"intersect", "union", "difference", "merge", "subtract"} do
  local a, b = graded("plate.stl", {1, 0}), graded("rod.stl", {0, 1})
  a[op](a, b):save("lua_" .. op .. ".vdb")
end
LUA
$HOVOX run ops.lua &&
for op in intersect union difference merge subtract; do
  $HOVOX boolean red.vdb $op blue.vdb -o cli_$op.vdb || exit 1
  if cmp -s cli_$op.vdb lua_$op.vdb; then echo "$op: identical with the UUID too?"; fi
  tail -c +59 cli_$op.vdb > a.bin; tail -c +59 lua_$op.vdb > b.bin
  cmp -s a.bin b.bin && echo "$op: the same model as Lua's" || echo "$op: DIFFERS from Lua's"
done
/usr/bin/python3 -c "
import json, sys, pyopenvdb as vdb
g, meta = vdb.readAll('cli_subtract.vdb')
d = json.loads(meta['hovox.geometry.json'])
print([l['name'] for l in d['leaves']], d['tree'])
"
