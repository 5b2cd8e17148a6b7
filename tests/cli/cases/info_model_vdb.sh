# issue 32 (h32 item 3): `hovox info MODEL.vdb` describes the model (it said "unsupported mesh
# format 'vdb'"): dims, voxel size, origin, box, grids, materials, regions and recorded shapes,
# as text and --json; a model is known by its content, not its name; a damaged one is refused
# (exit 1)
$HOVOX run tests/lua/scripts/assembly.lua "$TMP" >/dev/null &&
$HOVOX grade "$TMP/assembly.vdb" -o "$TMP/g.vdb" -q &&
(cd "$TMP" && $HOVOX voxelize assembly.stl -o plain.vdb --voxel-size 1 -q >/dev/null) &&
cp "$TMP/plain.vdb" "$TMP/plain.model" &&
cd "$TMP" && $HOVOX info g.vdb && $HOVOX info --json plain.model
echo "rc=$?"
head -c 300 plain.vdb > cut.vdb
$HOVOX info cut.vdb
echo "rc=$?"
