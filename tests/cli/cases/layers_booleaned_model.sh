# issue 28: a plate 20 x 10 x 2 minus a rod of radius 3 (CSG subtract; the holed plate of
# holed_plate.py, the one way the cases build it: the CLI's boolean, the same bytes as Lua's, case
# boolean_matches_lua) cut without a mesh: the model records both meshes and the tree, so every
# layer keeps the hole (a 1-bit layer drawn at 50 dpi); the manifest names the shape; the plate's
# own mesh given as --mesh is refused naming both, and nothing is written
here=$(pwd)
cd "$TMP" || exit 1
/usr/bin/python3 "$here/tests/cli/cases/holed_plate.py" 20,10,2 3 64 0.5 subtract holed.vdb &&
$HOVOX layers holed.vdb -o stack --mode mask --dpi 50,50 --layer-height 1 &&
grep '"mesh"' stack/manifest.json &&
/usr/bin/python3 -c "
import sys
sys.path.insert(0, sys.argv[1])
from png_read import pixels, read_png
for f in sys.argv[2:]:
    w, h, bd, ct, rows = read_png(f)
    print(f)
    for row in rows:
        print(''.join('#' if v else '.' for v in pixels(row, bd, 0, w)))
" "$here/tests/support" stack/layer-00000.png stack/layer-00001.png
$HOVOX layers holed.vdb --mesh plate.stl -o refused --mode mask --dpi 50,50 --layer-height 1
echo "rc=$?"; ls refused 2>&1 | sed 's/.*: //'
