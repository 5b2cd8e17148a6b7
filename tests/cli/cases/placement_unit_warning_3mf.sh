# A 3MF states its unit, so --unit is refused for it: its size warning names a --scale from the
# stated unit instead (before, "--unit in makes it ...", which the command then refuses). The hand
# writer's 10 x 6 x 4 box turned (6 x 10 x 4 mm) with its model unit set to micron (the warning's
# likely unit is the largest that fits the build volume, as for an STL: inches, 254 mm) and to
# meter (10 m: millimetres, 10 mm); the scale each warning names leaves no warning
p="$TMP/p.3mf"
unit() { /usr/bin/python3 -c "
import sys, zipfile
src, dst, unit = sys.argv[1:]
with zipfile.ZipFile(src) as a, zipfile.ZipFile(dst, 'w') as b:
    for n in a.namelist():
        d = a.read(n)
        b.writestr(n, d.replace(b\"unit='millimeter'\", (\"unit='%s'\" % unit).encode()))
" tests/data/good/3mf_hand_writer.3mf "$p" "$1"; }
unit micron
$HOVOX voxelize "$p" --dims 8 --dry-run | grep -E "^(placed|grid)"
$HOVOX voxelize "$p" --scale 25400 --dims 8 --dry-run | grep -E "^(placed|grid)"
unit meter
$HOVOX voxelize "$p" --dims 8 --dry-run | grep -E "^(placed|grid)"
$HOVOX voxelize "$p" --scale 0.001 --dims 8 --dry-run | grep -E "^(placed|grid)"
