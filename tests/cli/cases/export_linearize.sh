# a measured stiffness table in the fraction of b: at b = 7/11 (voxel 7) E = 1e7 + (7/11 - 0.5) / 0.5 * (1e9 - 1e7)
/usr/bin/python3 tests/cli/cases/export_model.py "$TMP/m.vdb" || exit 9
printf "# E of a/b blends (made up)\nfraction.b,youngs_modulus[Pa]\n0,1e6\n0.5,1e7\n1,1e9\n" >"$TMP/e.csv"
out=$($HOVOX export "$TMP/m.vdb" -o "$TMP/m.vti" --properties none --linearize youngs_modulus="$TMP/e.csv"); rc=$?
printf "%s\n" "$out" | sed -E "s/\([0-9]+ bytes\)/(N bytes)/"
[ $rc = 0 ] || exit $rc
/usr/bin/python3 tests/cli/cases/export_readback.py "$TMP/m.vti" 7
