# issue 28 check: a plain model (one recorded mesh, no Booleans) cut without --mesh gives the same
# J750 stack, every layer and the manifest byte for byte, as the same model cut with its own mesh;
# a different mesh as --mesh is refused (not a silent other shape)
cd "$TMP" || exit 1
$HOVOX generate gear teeth=12 -o gear.stl >/dev/null &&
$HOVOX voxelize gear.stl --voxel-size 0.5 -o gear.vdb -q >/dev/null || exit 1
$HOVOX layers gear.vdb --mesh gear.stl --profile j750 --mode mask -q -o with >/dev/null || exit 1
$HOVOX layers gear.vdb --profile j750 --mode mask -q -o without >/dev/null || exit 1
a=$(ls with | wc -l) b=$(ls without | wc -l) d=0
for f in with/*; do cmp -s "$f" "without/$(basename "$f")" || { d=$((d + 1)); echo "differs: $(basename "$f")"; }; done
echo "with --mesh: $a files, without: $b files, $d differ"
[ "$a" -gt 10 ] && echo "more than 10 files"
$HOVOX generate box min=0,0,0 max=20,20,5 -o box.stl >/dev/null &&
$HOVOX layers gear.vdb --mesh box.stl --profile j750 --mode mask -q -o refused
echo "rc=$?"; ls refused 2>&1 | sed 's/.*: //'
