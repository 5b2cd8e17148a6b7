# issue 28, bad input: a model whose Boolean tree refers to a mesh the model does not hold, and
# one whose recorded mesh is damaged. Every stage that takes the shape from the model (layers,
# contours, export, boolean, tray) refuses with one message naming the model and the operation, exit 1,
# and writes nothing
here=$(pwd)
cd "$TMP" || exit 1
/usr/bin/python3 "$here/tests/cli/cases/holed_plate.py" 8,4,2 1 32 0.5 subtract holed.vdb || exit 1
/usr/bin/python3 -c "
import json, pyopenvdb as vdb
g, meta = vdb.readAll('holed.vdb')
doc = json.loads(meta['hovox.geometry.json'])
rod = [l for l in doc['leaves'] if l['name'] == 'rod.stl'][0]
keys = [k for k in meta if k.startswith('hovox.geometry.leaf.')]
missing = dict(meta); del missing[[k for k in keys if k == rod['data']][0]]
vdb.write('missing.vdb', grids=g, metadata=missing)
damaged = dict(meta); k = [k for k in keys if k == rod['data']][0]
damaged[k] = damaged[k][:-8] + 'AAAAAAA='
vdb.write('damaged.vdb', grids=g, metadata=damaged)
"
for m in missing damaged; do
    $HOVOX layers $m.vdb -o stack-$m --mode mask --dpi 50,50 --layer-height 1; echo "layers rc=$?"
    $HOVOX contours $m.vdb -o $m.svg --layer-height 1; echo "contours rc=$?"
    $HOVOX export $m.vdb -o $m.stl -q; echo "export rc=$?"
    $HOVOX boolean $m.vdb union a.vdb -o $m-u.vdb -q; echo "boolean rc=$?"
    $HOVOX tray --part $m.vdb@20,370 -o tray-$m --mode mask --resin A=VeroCyan-V --resin B=VeroMagenta-V -q
    echo "tray rc=$?"
done
echo "files besides the inputs: $(ls | grep -v -c -E '^(plate|rod|a|b|holed|missing|damaged)\.(stl|vdb)$')"
