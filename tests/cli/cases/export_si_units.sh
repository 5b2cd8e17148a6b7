# property arrays are in SI units named in their names: known units are converted (g/cm^3 to
# kg/m^3, GPa to Pa), a value without a unit takes its property's SI unit
$HOVOX generate box sx=2 sy=2 sz=2 -o "$TMP/b.stl" >/dev/null
$HOVOX voxelize "$TMP/b.stl" -o "$TMP/b.vdb" --dims 4 >/dev/null
$HOVOX grade "$TMP/b.vdb" -o "$TMP/g.vdb" --materials A,B --frf plane:0,0,0:1,0,0 --ranges 0,2,0 --f d/dg \
    --ms 1,0 --me 0,1 --property A:density=1.18:g/cm^3 --property B:density=1180 \
    --property A:youngs_modulus=2:GPa --property B:youngs_modulus=1e9:Pa >/dev/null || exit 9
$HOVOX export "$TMP/g.vdb" -o "$TMP/g.vti" | grep arrays
/usr/bin/python3 - "$TMP/g.vti" <<'PY'
import sys
from vtkmodules.vtkIOXML import vtkXMLImageDataReader
r = vtkXMLImageDataReader(); r.SetFileName(sys.argv[1]); r.Update()
pd = r.GetOutput().GetPointData()
for name in ("density.voigt[kg/m^3]", "youngs_modulus.voigt[Pa]"):
    a = pd.GetArray(name)
    lo, hi = a.GetRange()
    print(name, "%.6g %.6g" % (lo, hi))
PY
