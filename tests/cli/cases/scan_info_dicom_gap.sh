# a DICOM series with one slice missing
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 20,24,18 --spacing 4,4,6 --formats dicom || exit 9
rm "$TMP/ph/dicom/$(/usr/bin/python3 -c "import pydicom,glob,os;print(os.path.basename(sorted(glob.glob('$TMP/ph/dicom/*'),key=lambda n:float(pydicom.dcmread(n).ImagePositionPatient[2]))[5]))")"
$HOVOX info "$TMP/ph/dicom"
