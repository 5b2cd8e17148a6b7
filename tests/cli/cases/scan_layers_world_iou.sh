# a scan's mask stack against the analytic ellipsoid rasterised at the same pixel centres and layer
# heights (tests/io/scan/stack_iou.py): IoU >= 0.995 whether the grid is axis-aligned (NIfTI),
# rotated 30 and 12 degrees (gzipped NIfTI) or flipped (a DICOM series): each lands where its world
# coordinates say; the same phantom as NIfTI, NRRD and MetaImage prints identical layers
P=tests/io/scan/make_phantom.py
/usr/bin/python3 $P "$TMP/ras" --size 80,96,72 --spacing 1,1,1.5 --formats nii,nrrd,mha >/dev/null || exit 9
/usr/bin/python3 $P "$TMP/rot" --size 80,96,72 --spacing 1,1,1.5 --affine rotated --formats nii.gz >/dev/null || exit 9
/usr/bin/python3 $P "$TMP/flip" --size 80,96,72 --spacing 1,1,1.5 --affine flip --formats dicom >/dev/null || exit 9
for v in ras/phantom.nii ras/phantom.nrrd ras/phantom.mha rot/phantom.nii.gz flip/dicom; do
    d="$TMP/s-$(echo $v | tr / _)"
    $HOVOX layers "$TMP/$v" --iso -480 --mode mask --dpi 100,100 --layer-height 1 -o "$d" -q >/dev/null || exit 8
    printf '%s: ' "$v"; /usr/bin/python3 tests/io/scan/stack_iou.py "$d" --min 0.995 || exit 7
done
for f in nrrd mha; do
    for l in "$TMP/s-ras_phantom.nii"/layer-*.png; do cmp -s "$l" "$TMP/s-ras_phantom.$f/$(basename $l)" || { echo "$f differs at $l"; exit 6; }; done
done
echo "NIfTI, NRRD and MetaImage layers identical"
# a whole-volume clean-up (--keep-largest) makes the model first and cuts its recorded iso-surface
# (marching squares); the direct path above evaluates the data at every pixel: the same shape
$HOVOX layers "$TMP/ras/phantom.nii" --iso -480 --keep-largest --mode mask --dpi 100,100 --layer-height 1 -o "$TMP/s-model" -q >/dev/null || exit 5
printf 'the model path: '; /usr/bin/python3 tests/io/scan/stack_iou.py "$TMP/s-model" --min 0.995 || exit 4
