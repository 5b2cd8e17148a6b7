# issue 29 item 1: painting is an option of the library's one step (hv_layers_mesh_model), so the
# CLI, Lua's mesh:layers{} and Python's mesh.layers() paint alike. A UV-textured cube (OBJ + MTL +
# PNG, written by Python): `hovox layers cube.obj` and mesh:layers{} write the same files, the
# manifest's colour (dE2000) included, by default and with colour_depth, core, intent; Lua's
# report carries the colour's figures. colour_depth beside materials is refused (exit 1, nothing
# written). (python/tests/test_api.py compares Python's bytes the same way.)
/usr/bin/python3 tests/colour/textured_cube.py "$TMP" >/dev/null
cd "$TMP" || exit 1
$HOVOX layers cube.obj -o cli --layers 150:153 -q | sed -n '/^voxels/p;/^colour/p;/^wrote/p'
$HOVOX layers cube.obj -o cli2 --layers 150:153 --colour-depth 0.5 --core '#808080' --intent relative -q \
    | sed -n '/^voxels/p;/^colour/p'
cat >one.lua <<'LUA'
local cube = hovox.load_mesh("cube.obj")
local r = cube:layers{dir = "lua", layers = {150, 153}}
print(r.first, r.last, r.colour.skin_voxels, string.format("%.2f %.2f", r.colour.mean_de2000_target,
      r.colour.mean_de2000_achieved))
r = cube:layers{dir = "lua2", layers = {150, 153}, colour_depth = 0.5, core = "#808080", intent = "relative"}
print(r.colour.skin_voxels)
local ok, err = pcall(cube.layers, cube, {dir = "x", colour_depth = 1, materials = {cube = "VeroClear"}})
print(ok, err)
LUA
$HOVOX run one.lua
echo "rc=$?"
diff -r cli lua && echo "default: the same files"
diff -r cli2 lua2 && echo "depth, core, intent: the same files"
/usr/bin/python3 -c "
import json
a, b = (json.load(open(d + '/manifest.json')) for d in ('cli', 'cli2'))
print(a['colour']['skin_voxels'], b['colour']['skin_voxels'], b['colour']['intent'], sorted(m['name'] for m in b['materials']))"
ls
