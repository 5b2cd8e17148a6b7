# issue 29: a painted model's stack reports the skin's dE2000 through the profile it was painted
# with. A tetrahedron painted red all through (--colour and --core the same red): every voxel's
# dE2000 is the one hovox colour gives red (mean = max = 20.97), in the summary and manifest.json.
# A render shows the requested red, not the resins' palette mixture (magenta and yellow: a green channel near half the red one).
printf 'v 0 0 0\nv 6 0 0\nv 0 6 0\nv 0 0 6\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' > "$TMP/tet.obj"
$HOVOX voxelize "$TMP/tet.obj" --voxel-size 0.25 --colour tet=#ff0000 --core '#ff0000' -o "$TMP/t.vdb" -q >/dev/null
$HOVOX colour '#ff0000'
$HOVOX layers "$TMP/t.vdb" -o "$TMP/st" --layers 20:22 | sed -n '/^material/,$p'
echo "rc=$?"
/usr/bin/python3 -c "
import json, sys
m = json.load(open(sys.argv[1]))
print(json.dumps(m['colour'], sort_keys=True))" "$TMP/st/manifest.json"
$HOVOX render "$TMP/t.vdb" -o "$TMP/t.png" -q --size 200,200 >/dev/null
/usr/bin/python3 -c "
import sys
from PIL import Image
px = [p for p in Image.open(sys.argv[1]).convert('RGB').getdata() if p != (255, 255, 255)]
px = [p for p in px if p[0] > 64]
g = sorted(p[1] / p[0] for p in px)[len(px) // 2]
b = sorted(p[2] / p[0] for p in px)[len(px) // 2]
print('render: %d object pixels, median green/red %.2f, blue/red %.2f' % (len(px), g, b))
sys.exit(0 if len(px) > 1000 and g < 0.1 and b < 0.1 else 1)" "$TMP/t.png"
echo "rc=$?"
