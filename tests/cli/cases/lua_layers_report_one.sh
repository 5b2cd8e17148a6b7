# review item 1: mesh:layers, model:layers and hovox.layers_scan return one report
# (hv_lua_push_layers_report): the same keys, materials included; colour = {skin_voxels for a
# painted model (mesh:layers' model is gone by then: hv_colour_skin.printer_voxels says which),
# printer_voxels for a scan's colour table, mean_de2000_target, max_de2000_target,
# mean_de2000_achieved}, each as the stack's manifest.json says it.
/usr/bin/python3 tests/colour/textured_cube.py "$TMP" >/dev/null || exit 9
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 20,24,18 --spacing 4,4,6 --formats nii >/dev/null || exit 9
printf 'HU,colour\n-1000,#ffffff00\n30,#d08070\n1000,#f0f0e0\n' > "$TMP/col.csv"
cd "$TMP" || exit 1
cat >r.lua <<'LUA'
local function keys(t)
    local k = {}
    for n in pairs(t) do k[#k + 1] = n end
    table.sort(k)
    return table.concat(k, " ")
end
local function show(name, r)
    print(name, keys(r))
    print("", "materials: " .. keys(r.materials))
    local c = r.colour
    print("", "colour: " .. keys(c))
    print("", string.format("%d %.4f %.4f %.4f", c.skin_voxels or c.printer_voxels, c.mean_de2000_target,
                            c.max_de2000_target, c.mean_de2000_achieved))
end
local cube = hovox.load_mesh("cube.obj")
show("mesh", cube:layers{dir = "m", layers = {150, 152}})
local model = hovox.voxelize(cube, {voxel_size = 0.5})
model:paint(cube, {colour_depth = 1})
show("model", model:layers{mesh = cube, dir = "v", layers = {150, 152}})
show("scan", hovox.layers_scan("ph/phantom.nii", {range = {-480, 500}, lut = "col.csv", dpi = {100, 100},
                                                   layer_height = 2, layers = {20, 22}, dir = "s"}))
LUA
$HOVOX run r.lua; echo "rc=$?"
for d in m v s; do
    /usr/bin/python3 -c 'import json,sys; c=json.load(open(sys.argv[1]))["colour"]
print("manifest", sys.argv[1].split("/")[0], " ".join(k for k in sorted(c) if "voxels" in k), "%d %.4f %.4f %.4f" % (c.get("skin_voxels", c.get("printer_voxels")), c["mean_de2000_target"], c["max_de2000_target"], c["mean_de2000_achieved"]))' "$d/manifest.json"
done
