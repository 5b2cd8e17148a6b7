#!/usr/bin/python3
"""tests/readme/make_stress.py OUT.vti - the README's stress field of the cantilever beam (100 x 20 x 10
mm, clamped at x = 0, tip load 100 N): |sigma| = |M(x) y / I| in MPa with M = P (L - x), I = b h^3 /
12, on a VTK image of 1 mm point spacing reaching 2 mm past the beam, written by VTK itself as an FEA tool would deliver it."""
import sys
import numpy as np
import vtk
from vtk.util import numpy_support
P, L, b, h = 100.0, 100.0, 10.0, 20.0
I = b * h ** 3 / 12
nx, ny, nz = 105, 25, 15
img = vtk.vtkImageData()
img.SetDimensions(nx, ny, nz)
img.SetSpacing(1, 1, 1)
img.SetOrigin(-2, -2, -2)
x = np.clip(np.arange(nx, dtype=float) - 2, 0, L)
y = np.arange(ny, dtype=float) - 2 - h / 2
s = np.abs(P * (L - x)[np.newaxis, np.newaxis, :] * y[np.newaxis, :, np.newaxis] / I) * np.ones((nz, 1, 1))
a = numpy_support.numpy_to_vtk(s.ravel().astype(np.float32).copy())
a.SetName('sigma')
img.GetPointData().AddArray(a)
w = vtk.vtkXMLImageDataWriter()
w.SetFileName(sys.argv[1])
w.SetInputData(img)
w.Write()
