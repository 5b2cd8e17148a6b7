# issue 27 "Bad input", taken all the way to a stack: a cyclic component graph, a singular build
# item transform, a component transform that is not finite, a unit the specification does not
# name and a composite whose values do not sum to 1 are each one message naming the object or
# element, the part and its line and column, exit 1, from `layers PART.3mf` and from a tray part;
# nothing is written.
for f in cyclic_component singular_transform nonfinite_transform unknown_unit composite_sum; do
    $HOVOX layers "tests/data/bad/3mf_$f.3mf" -o "$TMP/layers_$f" -q; echo "layers $f: rc=$?"
    $HOVOX tray --part "tests/data/bad/3mf_$f.3mf@40,40" -o "$TMP/tray_$f" -q; echo "tray $f: rc=$?"
done
ls "$TMP"
