# issue 32 item 11: a valid .vdb whose grids disagree is refused when it is loaded, naming the voxel:
# material.A moved 4,096 voxels away (by OpenVDB itself, as another tool would), or halved so the
# fractions no longer sum to 1. Before, probe reported fractions summing to 0 or 0.5 and layers
# and render used them.
$HOVOX generate box -o "$TMP/b.stl" >/dev/null
$HOVOX voxelize "$TMP/b.stl" --voxel-size 2 -o "$TMP/m.vdb"
$HOVOX grade "$TMP/m.vdb" -o "$TMP/g.vdb" --materials A,B --frf plane:0,0,0:0,0,1 --ranges 0,5,0 --ms 1,0 --me 0,1 -q
/usr/bin/python3 - "$TMP" <<'PY'
import sys, pyopenvdb as vdb
d = sys.argv[1]
grids, meta = vdb.readAll(d + '/g.vdb')
def rewrite(name, fn):
    out = []
    for g in grids:
        if g.name == 'material.A':
            h = vdb.FloatGrid()
            h.name, h.transform = g.name, g.transform
            acc = h.getAccessor()
            for it in g.citerOnValues():
                x, y, z = it.min
                fn(acc, (x, y, z), it.value)
            g = h
        out.append(g)
    vdb.write(d + '/' + name, grids=out, metadata=meta)
rewrite('moved.vdb', lambda acc, p, v: acc.setValueOn((p[0] + 4096, p[1], p[2]), v))
rewrite('halved.vdb', lambda acc, p, v: acc.setValueOn(p, v * 0.5))
PY
$HOVOX probe "$TMP/g.vdb" 10,10,3
for f in moved halved; do
    $HOVOX probe "$TMP/$f.vdb" 10,10,3; echo "rc=$?"
    $HOVOX render "$TMP/$f.vdb" -o "$TMP/$f.png" --size 16x16 -q; echo "rc=$?"
done
ls "$TMP" | grep png
