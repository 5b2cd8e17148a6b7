# a voxelized model without materials renders grey; check the PNG header (size, 8-bit RGBA)
$HOVOX generate sphere -o "$TMP/s.stl" >/dev/null && $HOVOX voxelize "$TMP/s.stl" --dims 24 -o "$TMP/s.vdb" -q >/dev/null &&
$HOVOX render "$TMP/s.vdb" --surface --size 64x48 -o "$TMP/s.png" && od -An -tu1 -j12 -N14 "$TMP/s.png"
