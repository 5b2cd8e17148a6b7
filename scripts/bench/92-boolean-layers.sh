# scripts/bench/92-boolean-layers.sh - issue 28: the shape a model records, in the print and in the
# file. (1) A J750 stack of the plate 40 x 20 x 10 minus a rod (hovox boolean subtract; each layer's
# outline: both meshes cut and combined by Clipper) against the stack of the plain plate (anchor);
# goal <= 1.1x. (2) The bytes a model grows by to record its mesh (the geometry document and the
# deflated, base64 leaf) against the mesh's binary STL gzipped (-6, anchor); goal <= 1x.
echo
echo "== issue 28: a Booleaned model's J750 stack (anchor: the plain plate's; goal <= 1.1x), the recorded mesh's bytes (anchor: STL gzipped; goal <= 1x)"
b=$work/boolean
mkdir -p "$b"
if [ ! -f "$b/holed.vdb" ]; then
    "$HOVOX" generate box min=0,0,0 max=40,20,10 -o "$b/plate.stl" >/dev/null
    "$HOVOX" generate cylinder base=20,10,-1 axis=2 length=12 radius=5 -o "$b/rod.stl" >/dev/null
    for p in plate rod; do "$HOVOX" voxelize "$b/$p.stl" --voxel-size 0.25 -o "$b/$p.vdb" -q >/dev/null; done
    "$HOVOX" grade "$b/plate.vdb" -o "$b/red.vdb" --materials A,B --frf plane:0,0,0:0,0,1 --ranges 0,0,0 --ms 1,0 --me 1,0 >/dev/null
    "$HOVOX" grade "$b/rod.vdb" -o "$b/blue.vdb" --materials A,B --frf plane:0,0,0:0,0,1 --ranges 0,0,0 --ms 0,1 --me 0,1 >/dev/null
    "$HOVOX" boolean "$b/red.vdb" subtract "$b/blue.vdb" -o "$b/holed.vdb" -q >/dev/null
fi
# runs interleaved by hand, so both stacks see the same machine load
pl=""
ho=""
i=0
while [ $i -lt "$runs" ]; do
    pl="$pl $(wall "$HOVOX" layers "$b/red.vdb" -o "$b/s_plain" --force -q)"
    ho="$ho $(wall "$HOVOX" layers "$b/holed.vdb" -o "$b/s_holed" --force -q)"
    i=$((i + 1))
done
# shellcheck disable=SC2086
t_plain=$(median_of $pl)
# shellcheck disable=SC2086
t_holed=$(median_of $ho)
printf "%-28s %7.3f s\n" "plate (plain), J750" "$t_plain"
printf "%-28s %7.3f s   %sx the plain plate\n" "plate - rod (2 meshes)" "$t_holed" "$(ratio "$t_holed" "$t_plain")"
# (2) on the bench knot of 200,000 facets
knot=$work/knot200k.stl
[ -f "$knot" ] || "$HOVOX" generate knot facets=200000 -o "$knot" >/dev/null
"$HOVOX" voxelize "$knot" --dims 128 -o "$b/knot.vdb" -q >/dev/null
/usr/bin/python3 - "$b/knot.vdb" "$knot" <<'PY'
import gzip, sys, pyopenvdb as vdb
_, meta = vdb.readAll(sys.argv[1])
rec = sum(len(k) + len(v) for k, v in meta.items() if k.startswith("hovox.geometry."))
stl = open(sys.argv[2], "rb").read()
gz = len(gzip.compress(stl, 6))
print("%-28s %7.1f KiB   %.3fx the STL gzipped (%.1f KiB; the STL %.1f KiB)" % ("knot 200k: record in model", rec / 1024, rec / gz, gz / 1024, len(stl) / 1024))
PY
