# issue 32.4: a stack directory named "out/", "out/." or "out/./" is out itself, the sandbox's
# output directory: refused (its temporary ".out.tmp-PID" would be made in the parent, renamed
# over out, and ".out.tmp-*" trees deleted there), as io.open, os.remove and hovox.mkdir of those
# names; "out/sub/" and "out/sub/." are written inside. Outside the sandbox, "DIR/." is DIR, not
# a bogus "out of memory".
mkdir -p "$TMP/work/out" && cd "$TMP/work" || exit 1
echo keep >out/mine.txt
$HOVOX generate box -o out/part.stl
cp "$OLDPWD/tests/cli/hostile_prelude.lua" attack.lua # out, try(): lines 1-5
cat >>attack.lua <<'LUA'
local box = hovox.generate.box{min = {0, 0, 0}, max = {10, 10, 10}}
local model = hovox.voxelize(box, {voxel_size = 1})
local tray = hovox.tray{}
tray:add{mesh = out .. "/part.stl", material = "VeroPureWhite"}
for _, d in ipairs{out .. "/", out .. "/.", out .. "/./", out .. "//", "./" .. out .. "/"} do
  try("layers " .. d, model.layers, model, {mesh = box, dir = d, mode = "mask", layers = {0, 1}, force = true})
  try("contours " .. d, hovox.contours, box, {layer_height = 5, per_layer = d})
  try("tray " .. d, tray.layers, tray, {dir = d, layers = {0, 1}, force = true})
  try("io.open " .. d, io.open, d, "w")
  try("os.remove " .. d, os.remove, d)
end
try("mkdir out/", hovox.mkdir, out .. "/")
try("mkdir out/new/deeper", hovox.mkdir, out .. "/new/deeper")
try("mkdir ../escape", hovox.mkdir, out .. "/../escape")
try("contours out/sub/", hovox.contours, box, {layer_height = 5, per_layer = out .. "/sub/"})
try("contours out/sub2/.", hovox.contours, box, {layer_height = 5, per_layer = out .. "/sub2/."})
LUA
$HOVOX run --sandbox --output-dir out attack.lua out; echo "rc=$?"
ls -A . out out/new
# the library itself: DIR/. and DIR/ name DIR
$HOVOX contours out/part.stl --layer-height 5 --per-layer plain/. -o plain.svg; echo "rc=$?"
$HOVOX contours out/part.stl --layer-height 5 --per-layer plain/ -o plain.svg; echo "rc=$?"
ls -A . plain
