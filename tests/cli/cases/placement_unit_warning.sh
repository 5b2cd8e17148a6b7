# issue 27 item 3: a mesh whose size suggests a wrong unit is warned about, naming the likely unit
# (the bunny as scans bring it, in metres: 0.155 mm wide); the unit given, the warning goes.
$HOVOX voxelize "$SHARED/meshes/bunny_1500.stl" --scale 0.1686 --dry-run | grep -E "^(placed|grid)"
$HOVOX voxelize "$SHARED/meshes/bunny_1500.stl" --scale 0.1686 --unit m --dry-run | grep -E "^(placed|grid)"
# too large for any printer: a file in micrometres read as mm
$HOVOX contours "$SHARED/meshes/bunny_1500.stl" --scale 30000 --layer-height 100 -o "$TMP/a.cli"
$HOVOX contours "$SHARED/meshes/bunny_1500.stl" --scale 30000 --unit um --layer-height 0.1 -o "$TMP/b.cli"
