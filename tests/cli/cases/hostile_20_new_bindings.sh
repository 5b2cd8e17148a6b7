# hostile script against the contour job, f tables, calibration tables and profile plots of this
# session: metatables, links out of the output directory, numeric paths, the memory limit reached
# inside the layer callback (the script stops, exit 3, at its line or, when the job is between two
# cancel checks, ended by the watchdog; nothing left behind either way)
mkdir -p "$TMP/out" "$TMP/outside" && ln -s "$TMP/outside" "$TMP/out/escape" && cd "$TMP" || exit 1
cp "$OLDPWD/tests/cli/hostile_prelude.lua" attack.lua # out, try(): lines 1-5
cat >>attack.lua <<'LUA'
local box = hovox.generate.box{min = {0, 0, 0}, max = {10, 10, 10}}
local model = hovox.voxelize(box, {voxel_size = 1})
local axis = hovox.axis{origin = {0, 0, 0}, direction = {0, 0, 1}}
-- 1. f table with a metatable whose __index frees the model and collects garbage
local evil = setmetatable({kind = "sine"}, {__index = function(t, k) model:free(); collectgarbage(); return 1 end})
try("f metatable", hovox.ags, {feature = axis, d_grad = 2, ms = {1, 0}, me = {0, 1}, f = evil})
-- 2. points whose pairs carry metatables
local p = setmetatable({}, {__index = function() collectgarbage(); return 0.5 end})
try("points metatable", hovox.ags, {feature = axis, d_grad = 2, ms = {1, 0}, me = {0, 1}, f = {kind = "table", points = {{0, 0}, p}}})
-- 3. calibration table with a metatable
try("calibration metatable", hovox.ags, {feature = axis, d_grad = 2, ms = {1, 0}, me = {0, 1},
    calibration = setmetatable({property = "E"}, {__index = function() return {{0, 1}, {1, 2}} end})})
-- 4. per_layer and output through a symlink in the output dir, and outside it
try("per_layer via link", hovox.contours, box, {layer_height = 5, per_layer = out .. "/escape/layers"})
try("output via link", hovox.contours, box, {layer_height = 5, output = out .. "/escape/x.svg"})
try("output outside", hovox.contours, box, {layer_height = 5, output = "/tmp/hx_outside/y.svg"})
try("per_layer .. up", hovox.contours, box, {layer_height = 5, per_layer = out .. "/../hx_up"})
-- 5. a numeric text option: the copy must outlive collectgarbage
try("numeric output path", hovox.contours, box, {layer_height = 5, output = 12345})
-- 6. profile plot through a link
local m2 = hovox.voxelize(box, {voxel_size = 1})
try("profile plot via link", m2.profile, m2, {from = {0, 0, 0}, to = {1, 1, 1}, plot = out .. "/escape/p.svg"})
-- 7. a contours job whose layer tables exceed the memory limit (3M)
try("memory in layer callback", hovox.contours, box, {layer_height = 0.0005, per_layer = out .. "/many", output = out .. "/many.cli"})
print("alive")
LUA
$HOVOX run --sandbox --output-dir out --max-memory 3M attack.lua out 2>err; echo "rc=$?"
sed -e 's/ (ended: .*)$//' -e 's/^hovox: attack.lua:[0-9]*:/hovox: attack.lua:/' err >&2
rm err
ls -A out outside
