# -q is quiet in every command that takes it: no progress bar and no summary on stdout (each
# command below prints "stdout: nothing" when it wrote nothing there); warnings and notes still
# go to stderr (the open mesh's flood warning, export's note on a model without materials);
# --json and --dry-run print what they were asked for; the files are written as without -q
cd "$TMP" || exit 1
q() { out=$("$@" -q); rc=$?; printf '%s: rc=%s, stdout: %s\n' "$2" "$rc" "${out:-nothing}"; }
$HOVOX generate box min=0,0,0 max=10,6,4 -o b.stl >/dev/null || exit 1
$HOVOX generate cylinder base=5,3,-1 axis=2 length=6 radius=2 -o r.stl >/dev/null || exit 1
q $HOVOX voxelize b.stl --voxel-size 0.5 -o b.vdb
q $HOVOX voxelize r.stl --voxel-size 0.5 -o r.vdb
q $HOVOX voxelize "$SHARED/good/open_square.stl" --fill flood --dims 8 -o o.vdb
q $HOVOX grade b.vdb -o a.vdb --materials A,B --frf plane:0,0,0:1,0,0 --ranges 0,10,0 --ms 1,0 --me 0,1
q $HOVOX grade r.vdb -o c.vdb --materials A,B --frf plane:0,0,0:1,0,0 --ranges 0,10,0 --ms 0,1 --me 0,1
q $HOVOX boolean a.vdb subtract c.vdb -o h.vdb
q $HOVOX contours b.stl --layer-height 1 -o b.svg
q $HOVOX export a.vdb -o a.vti
q $HOVOX export b.vdb -o b.vti
q $HOVOX export h.vdb -o h.stl
q $HOVOX render a.vdb -o a.png --size 32x32
q $HOVOX profile a.vdb --from 0,3,2 --to 10,3,2 --samples 5 -o p.csv
q $HOVOX layers a.vdb -o stack --dpi 50,50 --layer-height 1
q $HOVOX tray --part a.vdb@40,40 -o tray --resin A=VeroCyan-V --resin B=VeroMagenta-V --layers 0:2 --view
q $HOVOX view stack
echo 'print("the script prints")' > s.lua
q $HOVOX run s.lua
ls b.vdb r.vdb a.vdb c.vdb h.vdb b.svg a.vti b.vti h.stl a.png p.csv stack/index.html tray/index.html | wc -l
# asked for: the summary as JSON, the plan of a dry run
js='import json, sys; d = json.load(sys.stdin); print("json", sys.argv[1], d[sys.argv[1]])'
$HOVOX voxelize b.stl --voxel-size 0.5 -o j.vdb --json -q | /usr/bin/python3 -c "$js" occupied
$HOVOX contours b.stl --layer-height 1 --json -q | /usr/bin/python3 -c "$js" count
$HOVOX export a.vdb -o x.vti --dry-run -q | grep '^image'
$HOVOX layers a.vdb -o x --dpi 50,50 --layer-height 1 --dry-run -q | grep '^layers'
$HOVOX tray --part a.vdb@40,40 -o x --resin A=VeroCyan-V --resin B=VeroMagenta-V --dry-run -q | grep '^parts'
ls x 2>&1 | sed 's/.*: //'
