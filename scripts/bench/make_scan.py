#!/usr/bin/python3
"""scripts/bench/make_scan.py OUT.nii - the bench's synthetic scan (issue 30): 512 x 512 x 400 int16
samples of 0.2 mm (NIfTI-1 by nibabel), a head-like ellipsoid (semi-axes 48, 46, 38 mm) in air
(-1000 HU): skin 40 HU, a skull shell 1000 HU between 0.8 and 0.9 of the radius, brain 30 HU."""
import sys

import nibabel as nib
import numpy as np

n = (512, 512, 400)
sp = 0.2
axes = np.array([48.0, 46.0, 38.0])
x = (np.arange(n[0]) - (n[0] - 1) / 2) * sp
y = (np.arange(n[1]) - (n[1] - 1) / 2) * sp
data = np.empty(n, np.int16)
X, Y = np.meshgrid(x, y, indexing="ij")
for k in range(n[2]):
    z = (k - (n[2] - 1) / 2) * sp
    r = np.sqrt((X / axes[0]) ** 2 + (Y / axes[1]) ** 2 + (z / axes[2]) ** 2)
    v = np.full(r.shape, -1000, np.int16)
    v[r <= 1.0] = 40
    v[r <= 0.9] = 1000
    v[r <= 0.8] = 30
    data[:, :, k] = v
A = np.diag([sp, sp, sp, 1.0])
A[:3, 3] = [-(n[0] - 1) / 2 * sp, -(n[1] - 1) / 2 * sp, -(n[2] - 1) / 2 * sp]
img = nib.Nifti1Image(data, A)
img.set_sform(A, code=1)
img.set_qform(A, code=1)
nib.save(img, sys.argv[1])
