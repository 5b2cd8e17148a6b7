# issue 29: a painted model's export carries the colours asked for: arrays colour.r, colour.g,
# colour.b in .vti (per voxel) and .vtu (per cell), read back by VTK's own readers: at the red
# face's skin (1, 0, 0), the green face's (0, 1, 0), 0 in the Agilus30 core (a resin, no colour)
$HOVOX voxelize samples/colour_cube.obj --voxel-size 0.5 --colour-depth 1 --core Agilus30 -o "$TMP/c.vdb" -q >/dev/null
$HOVOX export "$TMP/c.vdb" -o "$TMP/c.vti" | grep -E "^arrays"
$HOVOX export "$TMP/c.vdb" -o "$TMP/c.vtu" | grep -E "^arrays"
/usr/bin/python3 - "$TMP" <<'PY'
import sys
import vtk
d = sys.argv[1]
def rgb(data, loc, p):
    i = loc(p)
    arr = [data.GetArray(n) for n in ("colour.r", "colour.g", "colour.b")]
    return tuple(round(a.GetValue(i), 3) for a in arr)
r = vtk.vtkXMLImageDataReader(); r.SetFileName(d + "/c.vti"); r.Update()
img = r.GetOutput()
u = vtk.vtkXMLUnstructuredGridReader(); u.SetFileName(d + "/c.vtu"); u.Update()
grid = u.GetOutput()
cl = vtk.vtkCellLocator(); cl.SetDataSet(grid); cl.BuildLocator()
for name, p in (("red skin", (5.25, 5.25, 0.25)), ("green skin", (5.25, 5.25, 9.75)), ("core", (5.25, 5.25, 5.25))):
    print("%-10s vti %s vtu %s" % (name, rgb(img.GetPointData(), img.FindPoint, p), rgb(grid.GetCellData(), cl.FindCell, p)))
PY
echo "rc=$?"
