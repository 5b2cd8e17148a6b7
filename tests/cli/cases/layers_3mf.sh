# hovox layers on a .3mf: the package's own mesh and its graded model, no --mesh
$HOVOX layers tests/data/good/volumetric_box.3mf -o "$TMP/st" --dpi 25.4,25.4 --layer-height 0.5 --mode fractions; rc=$?
ls "$TMP/st" "$TMP/st/Agilus" | head -8
exit $rc
