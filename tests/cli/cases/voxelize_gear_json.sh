$HOVOX voxelize "$SHARED/meshes/helical_gear.stl" --dims 64 -o "$TMP/gear.vdb" --json -q && vdb_print "$TMP/gear.vdb" | grep -o "occupancy\|surface" | sort -u
