# issue 28: a plate 20 x 10 x 2 minus a rod of radius 3 (Lua's CSG subtract) cut without a mesh:
# the model records both meshes and the tree, so every layer keeps the hole (a 1-bit layer drawn
# at 50 dpi); the manifest names the shape; the plate's own mesh given as --mesh is refused
# naming both, and nothing is written
cd "$TMP" || exit 1
$HOVOX generate box min=0,0,0 max=20,10,2 -o plate.stl &&
$HOVOX generate cylinder base=10,5,-1 axis=2 length=4 radius=3 segments=64 -o rod.stl &&
cat > holed.lua <<'LUA'
local mats = hovox.materials{{name = "A", color = "#ff0000"}, {name = "B", color = "#0000ff"}}
local plate = hovox.object(hovox.voxelize(hovox.load_mesh("plate.stl"), {voxel_size = 0.5}), mats)
local rod = hovox.object(hovox.voxelize(hovox.load_mesh("rod.stl"), {voxel_size = 0.5}), mats)
plate:subtract(rod):save("holed.vdb")
LUA
$HOVOX run holed.lua &&
$HOVOX layers holed.vdb -o stack --mode mask --dpi 50,50 --layer-height 1 &&
grep '"mesh"' stack/manifest.json &&
/usr/bin/python3 -c "
import zlib, struct, sys
for f in sys.argv[1:]:
    d = open(f, 'rb').read(); w, h, bd = struct.unpack('>IIB', d[16:25]); pos = 8; idat = b''
    while pos < len(d):
        n, = struct.unpack('>I', d[pos:pos+4])
        if d[pos+4:pos+8] == b'IDAT': idat += d[pos+8:pos+8+n]
        pos += 12 + n
    raw = zlib.decompress(idat); stride = (w * bd + 7) // 8
    print(f)
    for y in range(h):
        row = raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)]
        print(''.join('#' if (row[x // 8] >> (7 - x % 8)) & 1 else '.' for x in range(w)))
" stack/layer-00000.png stack/layer-00001.png
$HOVOX layers holed.vdb --mesh plate.stl -o refused --mode mask --dpi 50,50 --layer-height 1
echo "rc=$?"; ls refused 2>&1 | sed 's/.*: //'
