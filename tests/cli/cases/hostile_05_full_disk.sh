# issue 19.5: a write that fails (the file-size limit stands in for a full disk, and /dev/full)
# is an I/O error (exit 4), the good model under the name stays, and no temporary is left
$HOVOX generate box -o "$TMP/b.stl"
$HOVOX voxelize "$TMP/b.stl" -o "$TMP/m.vdb" --dims 16 -q >/dev/null && cp "$TMP/m.vdb" "$TMP/good.vdb"
(trap '' XFSZ; ulimit -f 16; $HOVOX voxelize "$TMP/b.stl" -o "$TMP/m.vdb" --dims 96 -q >/dev/null); echo "rc=$?"
cmp "$TMP/m.vdb" "$TMP/good.vdb" && echo "the good model is still there"
ls -a "$TMP" | grep -c tmp-
$HOVOX voxelize "$TMP/b.stl" -o /dev/full --dims 16 -q >/dev/null; echo "rc=$?"
$HOVOX generate box -o /dev/full; echo "rc=$?"
