# design by property and by data (issue 18): a graded source through a calibration table, a
# field feature from a .vti (its range printed); bad tables and bad fields are bad input (exit 1)
# with one message naming the file and the place, a missing file is I/O (exit 4); nothing is
# written by a failed run
$HOVOX generate box sx=20 sy=10 sz=6 -o "$TMP/b.stl" >/dev/null
$HOVOX voxelize "$TMP/b.stl" -o "$TMP/b.vdb" --voxel-size 1 >/dev/null
printf '# modulus of rigid/rubber blends\nt,youngs_modulus[MPa]\n0,0.6\n0.5,9.5\n0.8,250\n1,2000\n' >"$TMP/cal.csv"
printf 't,youngs_modulus[MPa]\n0,0.6\n0.5,9.5\n0.8,5\n1,2000\n' >"$TMP/nonmono.csv"
printf 't,youngs_modulus[MPa]\n0,0.6\n0.5,nan\n1,2000\n' >"$TMP/nan.csv"
: >"$TMP/empty.csv"
printf 'fraction.A,youngs_modulus\n0,0.6\n1,2000\n' >"$TMP/header.csv"
# a 2 x 2 x 2 image far from the model, and one over it with f = x + 2y and a vector array
vti() { # origin spacing
    printf '<?xml version="1.0"?>\n<VTKFile type="ImageData" version="0.1" byte_order="LittleEndian">\n'
    printf '<ImageData WholeExtent="0 1 0 1 0 1" Origin="%s" Spacing="%s">\n<Piece Extent="0 1 0 1 0 1">\n' "$1" "$2"
    printf '<PointData>\n<DataArray type="Float64" Name="f" format="ascii">%s</DataArray>\n' "$3"
    printf '<DataArray type="Float64" Name="v" NumberOfComponents="3" format="ascii">'
    printf '0 0 0 %.0s' 1 2 3 4 5 6 7 8
    printf '</DataArray>\n</PointData>\n</Piece>\n</ImageData>\n</VTKFile>\n'
}
vti "100 100 100" "1 1 1" "0 0 0 0 0 0 0 0" >"$TMP/far.vti"
vti "-5 -5 -5" "30 30 30" "-15 15 45 75 -15 15 45 75" >"$TMP/f.vti"
G="--materials rigid,rubber"; S="--ms 0,1 --me 1,0"
$HOVOX grade "$TMP/b.vdb" -o "$TMP/ok.vdb" $G --frf plane:0,0,0:1,0,0 --ranges 2,16,2 $S \
    --calibration "$TMP/cal.csv" --property-grading youngs_modulus --ps 1MPa --pe 1GPa --log
echo "rc=$?"
$HOVOX probe "$TMP/ok.vdb" 10,5,3
$HOVOX grade "$TMP/b.vdb" -o "$TMP/field.vdb" $G --frf field:"$TMP/f.vti":f --ranges 0,40,0 $S
echo "rc=$?"
$HOVOX probe "$TMP/field.vdb" 10,5,3
for t in nonmono nan empty header missing; do
    $HOVOX grade "$TMP/b.vdb" -o "$TMP/bad_$t.vdb" $G --frf plane:0,0,0:1,0,0 --ranges 2,16,2 $S --calibration "$TMP/$t.csv"
    echo "rc=$?"
done
$HOVOX grade "$TMP/b.vdb" -o "$TMP/bad_unit.vdb" $G --frf plane:0,0,0:1,0,0 --ranges 2,16,2 $S \
    --calibration "$TMP/cal.csv" --property-grading youngs_modulus --ps 85ShoreA --pe 1GPa
echo "rc=$?"
$HOVOX grade "$TMP/b.vdb" -o "$TMP/bad_range.vdb" $G --frf plane:0,0,0:1,0,0 --ranges 2,16,2 $S \
    --calibration "$TMP/cal.csv" --property-grading youngs_modulus --ps 1MPa --pe 3GPa
echo "rc=$?"
for spec in "$TMP/f.vti:sigma" "$TMP/f.vti:v" "$TMP/far.vti:f"; do
    $HOVOX grade "$TMP/b.vdb" -o "$TMP/bad_field.vdb" $G --frf "field:$spec" --ranges 0,40,0 $S
    echo "rc=$?"
done
ls "$TMP" | grep -c '^bad_'
