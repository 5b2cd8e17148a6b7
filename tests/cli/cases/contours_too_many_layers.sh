# a plan of more layers than the slicer takes is a resource refusal naming the count (layer
# heights below 0.1 um are refused as values already: the tall box reaches the limit instead)
$HOVOX generate box sx=1 sy=1 sz=2000 -o "$TMP/tall.stl" &&
$HOVOX contours "$TMP/tall.stl" --layer-height 0.0001 -o "$TMP/x.cli"; rc=$?; ls "$TMP"; exit $rc
