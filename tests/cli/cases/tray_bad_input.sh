# Refused trays (issue 14, "Bad input"): one line naming the part, the job file's line and
# column or the value; exit 1 or 2; nothing written.
cd "$TMP"
"$HOVOX" generate box max=20,10,2 -o b.stl >/dev/null
job() { printf '%s\n' "$1" >j.json; "$HOVOX" tray j.json -o out; echo "rc=$?"; }
job '{"parts": [{"mesh": "b.stl", "material": "VeroPureWhite", "at": [40, 40]},
 {"mesh": "b.stl", "material": "VeroPureWhite", "at": [50, 40]}]}'
job '{"parts": [{"mesh": "b.stl", "material": "VeroPureWhite", "at": [485, 40]}]}'
job '{"parts": [{"mesh": "b.stl", "material": "Gold", "at": [40, 40]}]}'
job '{"resin": {"X": "Gold"}, "parts": [{"mesh": "b.stl", "material": "X", "at": [40, 40]}]}'
job '{"parts": [{"mesh": "b.stl", "material": "VeroPureWhite", "at": [40, 40], "rotatoin": 90}]}'
job '{"parts": [{"mesh": "b.stl", "material": "VeroPureWhite", "at": [40, 40], "rotation": "ninety"}]}'
job '{"parts": [{"mesh": "missing.stl", "material": "VeroPureWhite", "at": [40, 40]}]}'
job '{"parts": [{"mesh": "b.stl", "material": "VeroPureWhite", "at": [40, 40], "z": 199}]}'
job '{"parts": [{"mesh": "b.stl", "material": "VeroPureWhite",, "at": [40, 40]}]}'
job '{"schema": 2, "parts": []}'
job '{"parts": [{"mesh": "b.stl", "material": "VeroPureWhite"}]}'
# a model with a mesh that is not its own
"$HOVOX" generate box max=5,5,1 -o s.stl >/dev/null
"$HOVOX" voxelize s.stl --voxel-size 0.5 -o s_occ.vdb -q >/dev/null
"$HOVOX" grade s_occ.vdb -o s.vdb --materials A --frf point:0,0,0 --ranges 0,0,0 --ms 1 --me 1 -q
"$HOVOX" tray -o out --part s.vdb,b.stl@40,40 --resin A=VeroCyan-V; echo "rc=$?"
rm -f s.stl s_occ.vdb s.vdb
"$HOVOX" tray -o out --part b.stl@40,40; echo "rc=$?"
"$HOVOX" tray -o out; echo "rc=$?"
"$HOVOX" tray --part b.stl:VeroPureWhite@40,40; echo "rc=$?"
ls
