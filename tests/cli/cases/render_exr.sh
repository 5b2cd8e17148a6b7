# EXR through the OpenImageIO plugin: the file starts with the OpenEXR magic number
$HOVOX generate sphere -o "$TMP/s.stl" >/dev/null && $HOVOX voxelize "$TMP/s.stl" --dims 16 -o "$TMP/s.vdb" -q >/dev/null &&
$HOVOX render "$TMP/s.vdb" --view top --size 16x16 -o "$TMP/s.exr" && od -An -tx1 -N4 "$TMP/s.exr"
