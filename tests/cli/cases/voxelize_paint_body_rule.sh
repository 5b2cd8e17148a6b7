# issue 29 item 2: `voxelize --colour-depth` and Lua model:paint paint an assembly by the body rule of
# `layers MESH` (hv_colour_mesh_paint): badge.3mf (tests/colour/colour_assembly.py, written by
# Python) voxelized at 0.5 mm and painted 1 mm deep keeps its plate in Agilus30Black (a resin: it
# was painted in its displaycolor #383838 before), paints the badge's colour group and the grip's
# "PLA Blue" displaycolor (colour asked for). Lua's painted model sliced in memory writes the bytes
# of `layers badge.3mf --voxel-size 0.5 --colour-depth 1` (plate and grip at layer 74, the badge at
# 222); saved, it is voxelize's model (the same layers; a .vdb keeps fractions in 16 bits, so the
# saved model's layers are compared with each other). A single coloured body paints as before
# (voxelize_colour, voxelize_colour_textured unchanged; unit test paint_follows_the_body_rule_of_layers).
/usr/bin/python3 tests/colour/colour_assembly.py "$TMP" >/dev/null || exit 9
cd "$TMP" || exit 9
$HOVOX voxelize badge.3mf --voxel-size 0.5 --colour-depth 1 -o v.vdb | sed -n '/^region/p;/^colour/p;/^slots/p;/^bodies/p'
echo "rc=$?"
$HOVOX probe v.vdb 10,10,2 4,10,6.25 26,10,2.25
cat >p.lua <<'LUA'
local mesh = hovox.load_mesh("badge.3mf")
local model = hovox.voxelize(mesh, {voxel_size = 0.5})
model:paint(mesh, {colour_depth = 1})
model:save("lua.vdb")
for _, l in ipairs{74, 222} do model:layers{dir = "l" .. l, mesh = mesh, layers = {l, l + 1}} end
LUA
$HOVOX run p.lua; echo "rc=$?"
for L in 74 222; do
    $HOVOX layers badge.3mf --voxel-size 0.5 --colour-depth 1 -o m$L --layers $L:$((L + 1)) -q
    $HOVOX layers v.vdb -o v$L --layers $L:$((L + 1)) -q
    $HOVOX layers lua.vdb -o s$L --layers $L:$((L + 1)) -q
    f=layer-$(printf %05d $L).png
    cmp m$L/$f l$L/$f && echo "layer $L: model:paint and layers MESH the same bytes"
    cmp v$L/$f s$L/$f && echo "layer $L: voxelize and model:paint (saved) the same bytes"
done
