# The bindings added in stop 38 (mesh:layers, hovox.layers_scan, tray:add's materials, scan and
# colour keys) against a hostile script under --sandbox: option tables (and nested ones) with
# an __index that frees the mesh and collects garbage are refused before any script code runs;
# a mesh freed by a finalizer before the call is "object was freed"; dir as a table, with a NUL,
# outside, naming the output directory itself, through ".." and through a planted symbolic link
# that leads out: refused; bytecode refused; an endless loop inside pcall ends at --max-time
# (exit 3). Nothing is written outside out/.
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/work/ph" --size 20,24,18 --spacing 4,4,6 --formats nii >/dev/null || exit 9
mkdir -p "$TMP/work/out" "$TMP/outside" && cd "$TMP/work" || exit 1
ln -s "$TMP/outside" out/ln
printf 'HU,VeroClear,Agilus30,VeroWhite\n-1000,1,0,0\n0,0,1,0\n1000,0,0,1\n' >bone.csv
$HOVOX generate box size=20,10,5 -o plate.stl >/dev/null
cp "$OLDPWD/tests/cli/hostile_prelude.lua" attack.lua # out, try(): lines 1-5
cat >>attack.lua <<'LUA'
local m = hovox.load_mesh("plate.stl")
local evil = {__index = function() m:free(); collectgarbage(); return nil end}
try("mesh:layers metatable", m.layers, m, setmetatable({dir = out .. "/s1", mode = "mask"}, evil))
try("mesh:layers materials metatable", m.layers, m, {dir = out .. "/s2", materials = setmetatable({}, evil)})
local m3 = hovox.load_mesh("plate.stl")
setmetatable({}, {__gc = function() m3:free() end})
collectgarbage()
try("mesh:layers freed by a finalizer", m3.layers, m3, {dir = out .. "/s3", mode = "mask"})
for _, d in ipairs{"/tmp/hovox-escape", out .. "/", out .. "/../escape", out .. "/ln/escape", out .. "/a\0b"} do
  try("mesh:layers " .. d:gsub("%z", "\\0"), m.layers, m, {dir = d, mode = "mask"})
  try("layers_scan " .. d:gsub("%z", "\\0"), hovox.layers_scan, "ph/phantom.nii", {dir = d, iso = -480, lut = "bone.csv"})
end
try("mesh:layers dir table", m.layers, m, {dir = setmetatable({}, {__tostring = function() return "/tmp/x" end})})
try("layers_scan metatable", hovox.layers_scan, "ph/phantom.nii", setmetatable({dir = out .. "/k1", iso = -480, lut = "bone.csv"}, evil))
local t = hovox.tray()
try("tray:add materials metatable", t.add, t, {mesh = "plate.stl", materials = setmetatable({}, evil), at = {50, 50}})
try("tray:add scan", t.add, t, {scan = "ph/phantom.nii", iso = -480, lut = "bone.csv", at = {150, 150}})
try("tray:layers through the link", t.layers, t, {dir = out .. "/ln/escape", layers = "0:2"})
try("bytecode", load(string.dump(function() return 1 end), nil, "b"))
while true do pcall(function() while true do end end) end
LUA
$HOVOX run --sandbox --max-time 2 --output-dir out attack.lua out; echo "rc=$?"
ls -A "$TMP/outside" out; ls -d /tmp/hovox-escape ../escape 2>/dev/null
