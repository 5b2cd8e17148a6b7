# issue 27: 3MF composite materials are material fractions. tests/data/good/composite_core.3mf
# holds a VeroWhite shell, its core of composite 6#0 (VeroWhite 0.25, Agilus30 0.75) and a tab of
# a multiproperties whose material layer is composite 6#1 (half and half) and whose colour layer is
# #3060C0: info lists the mixtures, voxelize carries them to the regions, grade (no source) gives
# each region its mixture's fractions, probed in the shell, the core and the tab. A composite whose
# values do not sum to 1 is refused naming its element and line, exit 1, nothing written.
m=tests/data/good/composite_core.3mf
$HOVOX info $m | sed -n '/^materials/,/^corner/p' &&
$HOVOX voxelize $m -o "$TMP/a.vdb" --voxel-size 0.5 | grep '^region' &&
$HOVOX grade "$TMP/a.vdb" -o "$TMP/g.vdb" &&
$HOVOX probe "$TMP/g.vdb" 1,1,1 5,5,5 13,13,13
echo "rc=$?"
$HOVOX voxelize tests/data/bad/3mf_composite_sum.3mf -o "$TMP/bad.vdb" --voxel-size 0.5
echo "rc=$?"
ls "$TMP"
