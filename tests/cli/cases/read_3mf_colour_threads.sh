# issue 29 item 4: a 3MF colour is sampled on the library's threads (each slab's sheets decoded once
# on one thread, in order; its leaves sampled in parallel; the six resins' fractions by leaf in
# parallel): the model read on 1 and on 2 threads is the same, byte for byte (its .vti export
# compared), for hovox's painted cube with its composite taken out (a colour printer's package,
# 0.25 mm: 125 leaves over 5 slabs, linear sheets) and for the turned package of
# tests/colour/colour_package.py (its own lattice, nearest and linear).
$HOVOX voxelize samples/colour_cube.obj --voxel-size 0.25 --colour-depth 1 --core Agilus30 -o "$TMP/c.vdb" -q || exit 9
$HOVOX export "$TMP/c.vdb" -o "$TMP/c.3mf" --volumetric -q >/dev/null || exit 9
/usr/bin/python3 tests/colour/colour_package.py write "$TMP" || exit 9
/usr/bin/python3 tests/colour/colour_alone.py "$TMP/c.3mf" "$TMP/alone.3mf" || exit 9
cd "$TMP" || exit 9
for p in alone turned nearest; do
    for t in 1 2; do HOVOX_THREADS=$t $HOVOX export $p.3mf -o $p$t.vti -q >/dev/null || echo "export $p $t failed"; done
    cmp $p"1.vti" $p"2.vti" && echo "$p: 1 and 2 threads the same model ($(wc -c <$p"1.vti") bytes of .vti)"
done
