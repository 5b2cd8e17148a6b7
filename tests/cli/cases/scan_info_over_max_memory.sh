# a 2 GiB NIfTI volume (1024^3 int16, a sparse file) over --max-memory 1G: refused before reading
/usr/bin/python3 -c '
import nibabel as nib, numpy as np, os, sys
h = nib.Nifti1Header(); h.set_data_shape((1024, 1024, 1024)); h.set_data_dtype(np.int16)
h.set_sform(np.diag([0.5, 0.5, 0.5, 1]), code=1); h["vox_offset"] = 352
p = sys.argv[1]
with open(p, "wb") as f:
    f.write(h.binaryblock + b"\0" * 4)
    f.truncate(352 + 2 ** 31)
' "$TMP/big.nii" || exit 9
$HOVOX info --max-memory 1G "$TMP/big.nii"
