# issue 29 item 3: a painted model's 3MF Volumetric package carries its colours as a <v:color> (an
# RGBA stack of 16 bits, linear sRGB, alpha where a colour was asked for) and hovox reads them back:
# the package's colour sheets (each a 16-bit RGBA PNG of the stack's size, read by VTK's PNG
# reader); `layers` of the package (its own outline, the voxels' boundary) measures the colour as
# the model's does; cut by the model's own mesh (--mesh), the package prints what the model prints:
# the targets within 0.01 and the same skin and dE2000 (the summaries side by side), and at every
# printer pixel more than a voxel from the colour depth the six fractions within 1/255 plus the
# output's rounding (--mode fractions; nearer, the model's stack splits each pixel by its side of the
# depth from its colour.depth grid, which the package does not carry: it interpolates, as a model
# painted before the grid); its render shows the same pixels as the model's (the colours asked for)
$HOVOX voxelize samples/colour_cube.obj --voxel-size 0.5 --colour-depth 1 --core Agilus30 -o "$TMP/c.vdb" >/dev/null || exit 9
$HOVOX export "$TMP/c.vdb" -o "$TMP/c.3mf" --volumetric | sed -E "s/\([0-9]+ bytes\)/(N bytes)/"
unzip -Z1 "$TMP/c.3mf" | grep -c '^3D/volumetric/colour/sheet....\.png$'
$HOVOX layers "$TMP/c.3mf" -o "$TMP/own" --dpi 254,254 --layer-height 0.1 | grep -E '^(mesh|colour)'
for src in c.vdb c.3mf; do
    mesh=; [ $src = c.3mf ] && mesh="--mesh samples/colour_cube.obj"
    $HOVOX layers "$TMP/$src" $mesh -o "$TMP/st_$src" --dpi 254,254 --layer-height 0.1 >"$TMP/$src.txt" || exit 8
    $HOVOX layers "$TMP/$src" $mesh -o "$TMP/fr_$src" --dpi 254,254 --layer-height 0.1 --mode fractions >/dev/null || exit 8
done
$HOVOX render "$TMP/c.vdb" -o "$TMP/c.vdb.png" >/dev/null || exit 7
$HOVOX render "$TMP/c.3mf" -o "$TMP/c.3mf.png" >/dev/null || exit 7
grep -E '^(  |colour)' "$TMP/c.vdb.txt" | cut -c1-80 >"$TMP/a"
grep -E '^(  |colour)' "$TMP/c.3mf.txt" | cut -c1-80 >"$TMP/b"
paste -d '|' "$TMP/a" "$TMP/b"
/usr/bin/python3 - "$TMP" <<'PY'
import json, os, sys, zipfile
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy
d = sys.argv[1]

def png(data):
    path = os.path.join(d, '.sheet.png')
    open(path, 'wb').write(data)
    r = vtk.vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    im = r.GetOutput()
    w, h, _ = im.GetDimensions()
    a = vtk_to_numpy(im.GetPointData().GetScalars())
    return w, h, im.GetNumberOfScalarComponents(), im.GetScalarType() == vtk.VTK_UNSIGNED_SHORT, a

z = zipfile.ZipFile(d + '/c.3mf')
sheets = sorted(n for n in z.namelist() if n.startswith('3D/volumetric/colour/'))
ok = all(png(z.read(n))[:4] == (22, 22, 4, True) for n in sheets)
print('colour sheets: %d, each 22 x 22 RGBA of 16 bits: %s' % (len(sheets), ok))

def stack(name):
    m = json.load(open(os.path.join(d, name, 'manifest.json')))
    layers = {}
    for l in m['layers']:
        planes = []
        for mat in m['materials']:
            w, h, _, _, a = png(open(os.path.join(d, name, l['files'][mat['name']]), 'rb').read())
            planes.append(np.flipud(a.reshape(h, w)).astype(float) / 255)
        layers[round(l['z_mm'], 6)] = np.array(planes)
    return m, layers

ma, la = stack('fr_c.vdb')
mb, lb = stack('fr_c.3mf')
assert [x['name'] for x in ma['materials']] == [x['name'] for x in mb['materials']]
px = ma['pixel_mm'][0]
dx = int(round((ma['origin_mm'][0] - mb['origin_mm'][0]) / px))
dy = int(round((mb['origin_mm'][1] - ma['origin_mm'][1]) / px))
worst, n, near = 0.0, 0, 0
for zmm, a in la.items():
    b = lb[zmm][:, dy:dy + a.shape[1], dx:dx + a.shape[2]]
    both = (a.sum(axis=0) > 0.5) & (b.sum(axis=0) > 0.5)
    # the 10 mm cube's depth (1 mm) within a voxel (0.5 mm) of the pixel centre: the model splits
    # such a pixel by its side (colour.depth), the package (which does not carry it) interpolates
    x = ma['origin_mm'][0] + (np.arange(a.shape[2]) + 0.5) * px
    y = ma['origin_mm'][1] - (np.arange(a.shape[1]) + 0.5) * px
    fx, fy = np.minimum(x, 10 - x), np.minimum(y, 10 - y)
    depth = np.minimum(np.minimum(fy[:, None], fx[None, :]), min(zmm, 10 - zmm))
    band = both & (np.abs(depth - 1) <= 0.5)
    both &= ~band
    near += int(band.sum())
    if both.any():
        worst = max(worst, float(np.abs(a - b)[:, both].max()))
        n += int(both.sum())
print('layers %d and %d; %d pixels in both more than a voxel from the colour depth: largest fraction difference '
      '%s 2/255 (%d within a voxel of it)' % (len(la), len(lb), n, 'within' if worst <= 2 / 255 + 1e-9 else
                                               'beyond (%.4f)' % worst, near))
ra, rb = png(open(d + '/c.vdb.png', 'rb').read()), png(open(d + '/c.3mf.png', 'rb').read())
print('render of the package: %d x %d, %d pixels unlike the model\'s' % (ra[0], ra[1], int((ra[4] != rb[4]).any(axis=-1).sum())
      if ra[:3] == rb[:3] else -1))
def targets(name):
    return [float(l.split()[1]) for l in open(os.path.join(d, name)) if l.startswith('  ')]
ta, tb = targets('c.vdb.txt'), targets('c.3mf.txt')
print('targets: %d materials, largest difference %s 0.01' % (len(ta), 'within' if len(ta) == len(tb) and
      max(abs(x - y) for x, y in zip(ta, tb)) <= 0.01 else 'beyond'))
PY
