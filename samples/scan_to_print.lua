-- samples/scan_to_print.lua - a scan straight to a print (issue 30): a CT-like head phantom is
-- written as an NRRD volume (as a scanner's export would be: Hounsfield units, left-posterior-
-- superior space), read back, its skin iso-surface made a part with no mesh, its materials taken
-- from a lookup table of Hounsfield units (air clear, soft tissue rubbery, bone rigid), then cut
-- open in a render, probed, and printed as a J750 stack straight from the data (hovox.layers_scan).
-- Outputs: the volume (.nrrd), the table (.csv), the model (.vdb), probes (.csv), a render (.png),
-- a J750 stack (PNG layers).
-- usage: hovox run samples/scan_to_print.lua [OUTDIR] [LAYERS]
--   LAYERS: the J750 layers to write, "A:B" (layers A to B-1), "all" (about 3700 layers) or "none"
--   (default 1850:1853, three layers through the middle)
-- test-args: 1850:1852
local out = arg[1] or "."
hovox.mkdir(out)
local stack = arg[2] or "1850:1853"

-- 1. the phantom: an ellipsoid head (semi-axes 36, 44, 50 mm) in shells, skin 40 HU, skull
-- 1000 HU (between 0.8 and 0.9 of the radius), brain 30 HU, in air (-1000 HU); 40 x 48 x 36
-- samples of 2 x 2 x 3 mm, each the mean of 2 x 2 x 2 points of its cell (partial volume)
local n, sp = {40, 48, 36}, {2, 2, 3}
local centre, axes = {2, -3, 5}, {36, 44, 50}
local origin = {} -- RAS of sample (0, 0, 0): the grid centred on the head
for a = 1, 3 do origin[a] = centre[a] - sp[a] * (n[a] - 1) / 2 end
local function hu(x, y, z)
    local q = ((x - centre[1]) / axes[1]) ^ 2 + ((y - centre[2]) / axes[2]) ^ 2 + ((z - centre[3]) / axes[3]) ^ 2
    local r = math.sqrt(q)
    if r <= 0.8 then return 30 elseif r <= 0.9 then return 1000 elseif r <= 1 then return 40 end
    return -1000
end
local values = {}
for k = 0, n[3] - 1 do
    for j = 0, n[2] - 1 do
        for i = 0, n[1] - 1 do
            local s = 0
            for c = 0, 7 do
                local dx, dy, dz = (c & 1) - 0.5, ((c >> 1) & 1) - 0.5, ((c >> 2) & 1) - 0.5
                s = s + hu(origin[1] + (i + dx / 2) * sp[1], origin[2] + (j + dy / 2) * sp[2],
                           origin[3] + (k + dz / 2) * sp[3])
            end
            values[#values + 1] = string.format("%d", math.floor(s / 8 + 0.5))
        end
    end
end
-- NRRD in LPS (DICOM's and ITK's space): x and y negated
local volume = out .. "/head_ct.nrrd"
local f = assert(io.open(volume, "w"))
f:write("NRRD0004\n# a CT-like head phantom (samples/scan_to_print.lua)\ntype: short\ndimension: 3\n",
        "space: left-posterior-superior\n", string.format("sizes: %d %d %d\n", n[1], n[2], n[3]),
        string.format("space directions: (%g,0,0) (0,%g,0) (0,0,%g)\n", -sp[1], -sp[2], sp[3]),
        string.format("space origin: (%g,%g,%g)\n", -origin[1], -origin[2], origin[3]),
        "kinds: domain domain domain\nendian: little\nencoding: ascii\n\n", table.concat(values, " "), "\n")
f:close()
local info = hovox.scan_info(volume)
print(string.format("volume: %s, %s, %d x %d x %d samples of %g x %g x %g mm, %g to %g, axes %s", volume, info.format,
                    info.dims[1], info.dims[2], info.dims[3], info.spacing[1], info.spacing[2], info.spacing[3],
                    info.value_min, info.value_max, info.axes))

-- 2. the lookup table: Hounsfield units to resins, linear between rows
local lut = out .. "/bone.csv"
f = assert(io.open(lut, "w"))
f:write("# Hounsfield units to resins: air clear, soft tissue rubbery, bone rigid\n",
        "HU,VeroClear,Agilus30Clear,VeroPureWhite\n-1000,1,0,0\n0,0,1,0\n300,0,1,0\n1000,0,0,1\n")
f:close()

-- 3. the part: the skin's iso-surface (halfway between air and skin), 1 mm voxels, materials from the table
local head = hovox.voxelize_scan(volume, {iso = -480, voxel_size = 1, lut = lut})
head:save(out .. "/head.vdb")
local analytic = 4 / 3 * math.pi * axes[1] * axes[2] * axes[3]
local voxels = head:voxels("occupancy")
print(string.format("model: %s, %d voxels of 1 mm^3 (the analytic head: %.0f mm^3, %+.2f%%)", out .. "/head.vdb", voxels,
                    analytic, 100 * (voxels - analytic) / analytic))
assert(math.abs(voxels - analytic) < 0.01 * analytic, "the iso-surface's volume is not within 1% of the analytic head's")

-- 4. probes across the head: brain, skull, skin
local probes = out .. "/probes.csv"
f = assert(io.open(probes, "w"))
f:write("x,y,z,VeroClear,Agilus30Clear,VeroPureWhite\n")
for _, p in ipairs{{2, -3, 5}, {2 + 0.85 * 36, -3, 5}, {2 + 0.95 * 36, -3, 5}} do
    local _, r = head:probe(p)
    f:write(string.format("%g,%g,%g,%.4f,%.4f,%.4f\n", p[1], p[2], p[3], r.VeroClear, r.Agilus30Clear, r.VeroPureWhite))
end
f:close()
print("probes: " .. probes)

-- 5. a render cut open, and the print
head:render{path = out .. "/head_cut.png", surface = true, clip = "x>2&y<-3", size = {360, 360}, background = "#202020"}
if stack ~= "none" then
    local range
    if stack ~= "all" then
        local a, b = stack:match("^(%d+):(%d+)$")
        assert(a, "LAYERS must be A:B, all or none, not " .. stack)
        range = {tonumber(a), tonumber(b)}
    end
    -- straight from the data, no model (as `hovox layers VOLUME` prints it): the shape and the table's
    -- materials at every printer pixel
    local st = hovox.layers_scan(volume, {iso = -480, lut = lut, dir = out .. "/head_j750", profile = "j750",
                                          layers = range})
    print(string.format("J750 stack: layers %d to %d of %d, %d x %d pixels; achieved VeroPureWhite %.4f, Agilus30Clear %.4f",
                        st.first, st.last - 1, st.layers, st.width, st.height, st.materials.VeroPureWhite.achieved,
                        st.materials.Agilus30Clear.achieved))
end
print("outputs in " .. out)
