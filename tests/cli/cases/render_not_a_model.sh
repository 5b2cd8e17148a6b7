$HOVOX render tests/data/good/tet_ascii.stl -o "$TMP/out.png"; echo "rc=$?"; ls "$TMP"
