# issue 29 item 2: a colour shares the printer's six slots with graded materials. A six-colour cube
# (no translucent colour) painted over an Agilus30Clear core: it takes a slot, VeroClear gives way
# (no voxel used it), and the planner says so; the stack has six resins whose targets sum to 1, in
# layers (one step) and in a tray; the tray's manifest carries the note. A seventh resin besides
# (a VeroUltraClear part) is refused naming the seven and how to map one onto a resin already used
# (exit 1, nothing written).
/usr/bin/python3 -c "
import sys; sys.path.insert(0, 'tests/colour'); import check_paint
check_paint.SIZE = 4; check_paint.write_cube(sys.argv[1])" "$TMP"
cd "$TMP"
"$HOVOX" layers cube.obj --core Agilus30Clear -o st --layers 40:42 | grep -E '^(voxels|slots|model|  )'
echo "rc=$?"
/usr/bin/python3 -c "
import json
m = json.load(open('st/manifest.json'))
print(len(m['materials']), 'resins:', ', '.join(x['name'] for x in m['materials']))
print('targets sum to %.6f' % sum(x['target'] for x in m['materials']))
print(m['colour']['gives_way'])"
"$HOVOX" tray --part cube.obj@40,30 --core Agilus30Clear -o tr --layers 40:42 | grep -E '^plate'
/usr/bin/python3 -c "
import json
m = json.load(open('tr/manifest.json'))
print([p['resin'] for p in m['palette'] if p['resin']])
print(m['parts'][0]['colour']['gives_way'])"
"$HOVOX" generate box max=4,4,4 -o plain.stl >/dev/null
"$HOVOX" tray --part cube.obj@40,30 --core Agilus30Clear --part plain.stl:VeroUltraClear@60,30 -o out; echo "rc=$?"
# a resin --resin-color adds takes a seventh slot: the message says how to map it onto a resin
# already used (the nearest in display colour), and doing so fits
"$HOVOX" tray --part cube.obj@40,30 --part plain.stl:Gold@60,30 --resin-color Gold=#d4af37 -o out; echo "rc=$?"
"$HOVOX" tray --part cube.obj@40,30 --part plain.stl:Gold@60,30 --resin-color Gold=#d4af37 --resin Gold=VeroYellow-V \
    -o out --dry-run | grep -E '^plate'
ls
