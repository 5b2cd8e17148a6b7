# the head phantom as NIfTI (nibabel), NRRD, MetaImage and a DICOM series (pydicom): one report each
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 20,24,18 --spacing 4,4,6 --formats nii.gz,nhdr,mha,dicom || exit 9
$HOVOX info "$TMP/ph/phantom.nii.gz" "$TMP/ph/phantom.nhdr" "$TMP/ph/phantom.mha" "$TMP/ph/dicom"
