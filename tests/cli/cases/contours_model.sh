# issue 28: contours of a model are those of the shape it records: a plain model's are its mesh's
# (the same CLI file but the label), a Boolean's (plate minus rod) have the hole in every layer;
# adaptive layers need one mesh
cd "$TMP" || exit 1
$HOVOX generate box min=0,0,0 max=20,10,2 -o plate.stl >/dev/null &&
$HOVOX generate cylinder base=10,5,-1 axis=2 length=4 radius=3 segments=16 -o rod.stl >/dev/null &&
cat > holed.lua <<'LUA'
local mats = hovox.materials{{name = "A"}, {name = "B"}}
local plate = hovox.voxelize(hovox.load_mesh("plate.stl"), {voxel_size = 0.5})
plate:save("plate.vdb")
local rod = hovox.object(hovox.voxelize(hovox.load_mesh("rod.stl"), {voxel_size = 0.5}), mats)
hovox.object(plate, mats):subtract(rod):save("holed.vdb")
LUA
$HOVOX run holed.lua &&
$HOVOX contours plate.stl --layer-height 1 -o mesh.cli && $HOVOX contours plate.vdb --layer-height 1 -o model.cli &&
diff mesh.cli model.cli
$HOVOX contours holed.vdb --layer-height 1 -o holed.cli && grep -c 'POLYLINE/1,0' holed.cli && sed -n '/GEOMETRYSTART/,$p' holed.cli | head -5
$HOVOX contours holed.vdb --adaptive 0.1,1 -o no.cli; echo "rc=$?"
