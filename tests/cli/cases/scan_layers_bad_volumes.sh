# bad volumes given to the commands that write (issue 30 checks): a truncated .nii.gz, a NRRD header
# that lies about its sizes, a DICOM series with a gap and one with a slice of another size, a 2 GiB
# volume over --max-memory: one message naming the file and the problem, exit 1 or 3, and neither
# `layers` (streaming) nor `voxelize` leaves anything behind
P=tests/io/scan/make_phantom.py
/usr/bin/python3 $P "$TMP/ph" --size 20,24,18 --spacing 4,4,6 --formats nii,nrrd.raw,dicom >/dev/null || exit 9
/usr/bin/python3 $P "$TMP/other" --size 22,24,18 --spacing 4,4,6 --formats dicom >/dev/null || exit 9
gzip -c "$TMP/ph/phantom.nii" | head -c 1500 > "$TMP/cut.nii.gz"
sed 's/^sizes: 20 24 18/sizes: 20 24 180/' "$TMP/ph/phantom_raw.nrrd" > "$TMP/lies.nrrd"
cp -r "$TMP/ph/dicom" "$TMP/gap"
rm "$TMP/gap/$(/usr/bin/python3 -c "import pydicom,glob,os;print(os.path.basename(sorted(glob.glob('$TMP/gap/*'),key=lambda n:float(pydicom.dcmread(n).ImagePositionPatient[2]))[5]))")"
cp -r "$TMP/ph/dicom" "$TMP/mixed"
cp "$TMP/other/dicom/$(ls "$TMP/other/dicom" | head -n 1)" "$TMP/mixed/zz_stranger.dcm"
/usr/bin/python3 -c '
import nibabel as nib, numpy as np, sys
h = nib.Nifti1Header(); h.set_data_shape((1024, 1024, 1024)); h.set_data_dtype(np.int16)
h.set_sform(np.diag([0.5, 0.5, 0.5, 1]), code=1); h["vox_offset"] = 352
with open(sys.argv[1], "wb") as f:
    f.write(h.binaryblock + b"\0" * 4)
    f.truncate(352 + 2 ** 31)
' "$TMP/big.nii" || exit 9
printf 'HU,A,B\n-1000,1,0\n1000,0,1\n' > "$TMP/t.csv"
mkdir "$TMP/out"
for v in cut.nii.gz lies.nrrd gap mixed big.nii; do
    $HOVOX layers "$TMP/$v" --iso -480 --lut "$TMP/t.csv" --max-memory 1G -o "$TMP/out/stack-$v"; echo "layers $v: rc=$?"
    $HOVOX voxelize "$TMP/$v" --iso -480 --max-memory 1G -o "$TMP/out/model-$v.vdb"; echo "voxelize $v: rc=$?"
done
echo "written: $(ls -A "$TMP/out" | wc -l)"
