$HOVOX contours tests/data/good/tet_ascii.stl --layer-height 1e-9 -o "$TMP/x.cli"; rc=$?; ls "$TMP"; exit $rc
