# issue 19.11: a temporary left by a killed process (its pid gone) is removed by the next write
# to the same name; one of a live process is not
$HOVOX generate box -o "$TMP/b.stl"
printf 'half a model' >"$TMP/.m.vdb.tmp-999999-0"
printf 'in use' >"$TMP/.m.vdb.tmp-1-0"
$HOVOX voxelize "$TMP/b.stl" -o "$TMP/m.vdb" --dims 8 -q >/dev/null; echo "rc=$?"
ls -a "$TMP" | grep m.vdb
