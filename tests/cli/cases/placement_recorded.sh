# issue 27 item 3 / DESIGN-ROUND "Placement": the model records the mesh as read and the placement
# as its leaf's 3x4 matrix and unit (geometry's record), not a second copy of the placed mesh.
cat >"$TMP/wedge.obj" <<'OBJ'
v 0 0 0
v 3 0 0
v 0 2 0
v 0 0 1
f 1 3 2
f 1 2 4
f 1 4 3
f 2 3 4
OBJ
$HOVOX voxelize "$TMP/wedge.obj" --unit cm --up y --translate 1,2,3 --dims 16 -o "$TMP/w.vdb" | grep -E "^(placed|grid)"
$HOVOX voxelize "$TMP/wedge.obj" --dims 16 -o "$TMP/raw.vdb" -q >/dev/null
cat >"$TMP/show.lua" <<'LUA'
for _, f in ipairs{arg[1] .. "/w.vdb", arg[1] .. "/raw.vdb"} do
    local doc = hovox.load(f):meta("hovox.geometry.json")
    print(doc:match('"transform": %b[]'), doc:match('"unit": [^,}]*'))
end
LUA
$HOVOX run "$TMP/show.lua" "$TMP"
