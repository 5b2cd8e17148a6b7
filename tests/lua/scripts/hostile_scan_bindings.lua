-- tests/lua/scripts/hostile_scan_bindings.lua - the scan bindings (hovox.scan_info, hovox.voxelize_scan;
-- issue 30) attacked as a hostile script would: option tables and label lists with metatables, absurd
-- shapes and sizes, lying or hostile files (a header that promises more than it holds, a directory
-- that is no DICOM series, a device), a colour table through a profile that is no profile, NUL bytes
-- in paths; every attempt is refused with a message or harmless.
-- tests/cli/cases/hostile_34_scan_bindings.sh runs it.
local out = arg[1]
local function try(name, fn, ...)
  local ok, err = pcall(fn, ...)
  print(name, ok and "ACCEPTED" or ("refused: " .. tostring(err):gsub("\n", " "):gsub(out, "OUT")))
end
local function write(path, text)
  local f = assert(io.open(path, "wb"))
  f:write(text)
  f:close()
end
-- a small honest volume: 4 x 4 x 4 int16, a 2 x 2 x 2 block of 100 in 0
local vals = {}
for k = 0, 3 do for j = 0, 3 do for i = 0, 3 do
  vals[#vals + 1] = (i >= 1 and i <= 2 and j >= 1 and j <= 2 and k >= 1 and k <= 2) and "100" or "0"
end end end
local head = "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 4 4\nspace: right-anterior-superior\n" ..
             "space directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: (0,0,0)\nendian: little\nencoding: ascii\n\n"
local vol = out .. "/v.nrrd"
write(vol, head .. table.concat(vals, " ") .. "\n")
write(out .. "/t.csv", "v,Soft,Hard\n0,1,0\n100,0,1\n")
write(out .. "/c.csv", "v,colour\n0,#ff0000\n100,#0000ff\n")
write(out .. "/notanicc.icc", "this is not an ICC profile")
-- 1. the honest call works
try("honest", function()
  local m = hovox.voxelize_scan(vol, {iso = 50, voxel_size = 0.5, lut = out .. "/t.csv"})
  local _, f = m:probe{1.5, 1.5, 1.5}
  assert(math.abs(f.Hard - 1) < 1e-3, "centre not Hard")
  return m
end)
try("info", function() local i = hovox.scan_info(vol); assert(i.dims[1] == 4 and i.value_max == 100) end)
-- 2. option tables and label lists with metatables
try("options with metatable", function()
  return hovox.voxelize_scan(vol, setmetatable({iso = 50}, {__index = function() return 1 end}))
end)
try("labels with metatable", function()
  return hovox.voxelize_scan(vol, {labels = setmetatable({100}, {__index = function() return 7 end})})
end)
try("labels not a list", function() return hovox.voxelize_scan(vol, {labels = "100"}) end)
try("labels empty", function() return hovox.voxelize_scan(vol, {labels = {}}) end)
try("labels fraction", function() return hovox.voxelize_scan(vol, {labels = {1.5}}) end)
try("labels 2^40", function() return hovox.voxelize_scan(vol, {labels = {1 << 40}}) end)
try("labels 70000", function() local l = {} for i = 1, 70000 do l[i] = i end return hovox.voxelize_scan(vol, {labels = l}) end)
try("labels 65536", function() local l = {} for i = 1, 65536 do l[i] = i - 1000 end return hovox.voxelize_scan(vol, {labels = l}) end)
-- 3. absurd shapes and sizes
try("no shape", function() return hovox.voxelize_scan(vol, {}) end)
try("iso and range", function() return hovox.voxelize_scan(vol, {iso = 1, range = {0, 1}}) end)
try("iso nan", function() return hovox.voxelize_scan(vol, {iso = 0 / 0}) end)
try("iso inf", function() return hovox.voxelize_scan(vol, {iso = math.huge}) end)
try("range inverted", function() return hovox.voxelize_scan(vol, {range = {5, 1}}) end)
try("voxel 1e-6", function() return hovox.voxelize_scan(vol, {iso = 50, voxel_size = 1e-6}) end)
try("voxel negative", function() return hovox.voxelize_scan(vol, {iso = 50, voxel_size = -1}) end)
try("min_feature huge", function() return hovox.voxelize_scan(vol, {iso = 50, min_feature = 1e300}) end)
try("max_memory 1", function() return hovox.voxelize_scan(vol, {iso = 50, max_memory = 1}) end)
try("unknown key", function() return hovox.voxelize_scan(vol, {iso = 50, mesh = true}) end)
try("icc without lut", function() return hovox.voxelize_scan(vol, {iso = 50, icc = out .. "/notanicc.icc"}) end)
try("colour through no profile", function()
  return hovox.voxelize_scan(vol, {iso = 50, lut = out .. "/c.csv", icc = out .. "/notanicc.icc"})
end)
try("lut a directory", function() return hovox.voxelize_scan(vol, {iso = 50, lut = out}) end)
try("lut a table", function() return hovox.voxelize_scan(vol, {iso = 50, lut = {}}) end)
-- 4. hostile files
write(out .. "/lie.nrrd", (head:gsub("sizes: 4 4 4", "sizes: 4000 4000 4000")) .. "0 0 0\n")
try("lying header", function() return hovox.voxelize_scan(out .. "/lie.nrrd", {iso = 1}) end)
try("not dicom", function() return hovox.scan_info(out) end)
try("device", function() return hovox.scan_info("/dev/zero") end)
try("NUL in path", function() return hovox.scan_info(vol .. "\0.nii") end)
try("path a table", function() return hovox.scan_info({}) end)
try("info max_memory 1", function() return hovox.scan_info(vol, {max_memory = 1}) end)
try("info unknown key", function() return hovox.scan_info(vol, {iso = 1}) end)
