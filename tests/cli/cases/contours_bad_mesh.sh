$HOVOX contours tests/data/bad/ascii_nan.stl --layer-height 0.1 -o "$TMP/x.cli"; rc=$?; ls "$TMP"; exit $rc
