# issue 32 item 16: features whose d changes sign. A half-space (signed distance to a plane, positive
# where its normal points) and a field of data that changes sign (written by VTK itself) grade with
# d- < 0: below d- the start composition, from d- over dg the gradient, above the end. A distance
# feature still refuses d- < 0, saying which features take it. Before, --ranges -5,10,0 was
# refused for every feature and plane: ignored the side.
$HOVOX generate box -o "$TMP/b.stl" >/dev/null
$HOVOX voxelize "$TMP/b.stl" --voxel-size 1 -o "$TMP/m.vdb" -q >/dev/null
$HOVOX grade "$TMP/m.vdb" -o "$TMP/h.vdb" --materials A,B --frf halfspace:10,0,0:1,0,0 --ranges -5,10,0 \
    --ms 1,0 --me 0,1 -q >/dev/null && echo "halfspace graded"
$HOVOX probe "$TMP/h.vdb" 2.5,10,10 7.5,10,10 10,10,10 12.5,10,10 17.5,10,10
/usr/bin/python3 - "$TMP/s.vti" <<'PY'
import sys, vtk
from vtk.util import numpy_support
import numpy as np
img = vtk.vtkImageData()
img.SetDimensions(49, 49, 49); img.SetSpacing(0.5, 0.5, 0.5); img.SetOrigin(-2, -2, -2)
x = -2 + np.arange(49) * 0.5
s = np.broadcast_to(x[np.newaxis, np.newaxis, :] - 10.0, (49, 49, 49)).ravel().astype(np.float32)  # x fastest
a = numpy_support.numpy_to_vtk(s.copy()); a.SetName('temperature')
img.GetPointData().AddArray(a)
w = vtk.vtkXMLImageDataWriter(); w.SetFileName(sys.argv[1]); w.SetInputData(img); w.Write()
PY
$HOVOX grade "$TMP/m.vdb" -o "$TMP/f.vdb" --materials A,B --frf field:"$TMP/s.vti":temperature --ranges -5,10,0 \
    --ms 1,0 --me 0,1 -q >/dev/null
$HOVOX probe "$TMP/f.vdb" 2.5,10,10 7.5,10,10 10,10,10 12.5,10,10 17.5,10,10
$HOVOX grade "$TMP/m.vdb" -o "$TMP/p.vdb" --materials A,B --frf plane:10,0,0:1,0,0 --ranges -5,10,0 --ms 1,0 --me 0,1
echo "rc=$?"
