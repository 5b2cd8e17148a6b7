# issue 19.6: an output that is one of the inputs, or whose extension is another format's, is
# refused before any work (exit 2) and the input is untouched
$HOVOX generate box -o "$TMP/in.stl" && cp "$TMP/in.stl" "$TMP/copy.stl"
$HOVOX voxelize "$TMP/in.stl" -o "$TMP/in.stl" --dims 8; echo "rc=$?"
$HOVOX voxelize "$TMP/in.stl" -o "$TMP/out.stl" --dims 8; echo "rc=$?"
cmp "$TMP/in.stl" "$TMP/copy.stl" && echo "the mesh is untouched"
$HOVOX voxelize "$TMP/in.stl" -o "$TMP/m.vdb" --dims 8 -q >/dev/null
$HOVOX grade "$TMP/m.vdb" -o "$TMP/m.vdb" --materials A --frf point:0,0,0 --ranges 0,0,0 --ms 1 --me 1; echo "rc=$?"
$HOVOX generate box -o "$TMP/box.vdb"; echo "rc=$?"
ls "$TMP"
