# 0.1 mm voxels of an 80 x 96 x 108 mm head: refused before any voxel, nothing written
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 20,24,18 --spacing 4,4,6 --formats nii.gz || exit 9
$HOVOX voxelize "$TMP/ph/phantom.nii.gz" --iso -480 --voxel-size 0.1 --max-memory 1G -o "$TMP/x.vdb"; rc=$?; ls "$TMP"; exit $rc
