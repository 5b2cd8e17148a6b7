# tests/cli/cases/export_readback.py - read a .vti/.vtu with VTK's own readers and print what
# the export CLI tests pin: geometry, array names and types, and values at a few points/cells.
#   export_readback.py FILE [INDEX ...]   (point ids for .vti, cell ids for .vtu)
import sys

import vtk
from vtk.util.numpy_support import vtk_to_numpy

path = sys.argv[1]
vti = path.endswith(".vti")
r = vtk.vtkXMLImageDataReader() if vti else vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(path)
r.Update()
if r.GetErrorCode() != 0:
    sys.exit("cannot read " + path)
d = r.GetOutput()
if vti:
    print("dims", *d.GetDimensions())
    print("origin", *("%.6g" % v for v in d.GetOrigin()))
    print("spacing", *("%.6g" % v for v in d.GetSpacing()))
    data = d.GetPointData()
else:
    print("cells", d.GetNumberOfCells(), "points", d.GetNumberOfPoints())
    print("types", *sorted(set(vtk_to_numpy(d.GetCellTypesArray()).tolist())))
    data = d.GetCellData()
for i in range(data.GetNumberOfArrays()):
    a = data.GetArray(i)
    print("array", a.GetName(), a.GetDataTypeAsString(), a.GetNumberOfTuples())
for s in sys.argv[2:]:
    k = int(s)
    if not vti:
        c = d.GetCell(k)
        lo = [min(c.GetPoints().GetPoint(v)[a] for v in range(8)) for a in range(3)]
        print("cell", k, "low corner", *("%.6g" % v for v in lo))
    else:
        print("point", k, "at", *("%.6g" % v for v in d.GetPoint(k)))
    for i in range(data.GetNumberOfArrays()):
        print("  %s = %.6g" % (data.GetArrayName(i), data.GetArray(i).GetTuple1(k)))
