# --property: the modulus from the calibration table stored with the model's source, a column
# youngs_modulus[MPa] (nan outside the object) and a plot with a right-hand axis; a model graded
# without a table, and a property the model has no table for, are bad input (exit 1) naming the
# model, the property and the tables it has, and nothing is written
$HOVOX generate box sx=20 sy=10 sz=6 -o "$TMP/b.stl" >/dev/null
$HOVOX voxelize "$TMP/b.stl" -o "$TMP/b.vdb" --voxel-size 1 >/dev/null
printf 't,youngs_modulus[MPa]\n0,0.6\n0.5,9.5\n0.8,250\n1,2000\n' >"$TMP/cal.csv"
G="--materials rigid,rubber --frf plane:-10,0,0:1,0,0 --ranges 2,16,2 --ms 0,1 --me 1,0"
$HOVOX grade "$TMP/b.vdb" -o "$TMP/cal.vdb" $G --calibration "$TMP/cal.csv" >/dev/null
$HOVOX grade "$TMP/b.vdb" -o "$TMP/plain.vdb" $G >/dev/null
$HOVOX profile "$TMP/cal.vdb" --from -11.5,0.5,0.5 --to 9.5,0.5,0.5 --samples 8 --property youngs_modulus \
    -o "$TMP/p.csv" --plot "$TMP/p.png"
echo "rc=$?"
cat "$TMP/p.csv"
od -An -c -j1 -N3 "$TMP/p.png"
$HOVOX profile "$TMP/plain.vdb" --from -9,0,0 --to 9,0,0 --property youngs_modulus -o "$TMP/bad1.csv" --plot "$TMP/bad1.png"
echo "rc=$?"
$HOVOX profile "$TMP/cal.vdb" --from -9,0,0 --to 9,0,0 --property shore_hardness -o "$TMP/bad2.csv"
echo "rc=$?"
ls "$TMP" | grep -c '^bad'
