# `tray --dry-run` lists where every part goes (issue 32 item 19: the arranged positions were
# not shown): given or arranged, copy, turn, lift and its box on the plate.
cd "$TMP"
"$HOVOX" generate box max=20,10,2 -o b.stl >/dev/null
"$HOVOX" generate box max=6,6,0.5 -o pin.stl >/dev/null
cat >job.json <<'JSON'
{"schema": 1, "arrange": "yes",
 "parts": [{"mesh": "b.stl", "material": "VeroPureWhite", "at": [100, 100], "rotation": 90, "z": 1},
           {"mesh": "b.stl", "material": "VeroCyan-V", "name": "bar", "at": [200, 100]},
           {"mesh": "pin.stl", "material": "VeroPureWhite", "copies": 3}]}
JSON
"$HOVOX" tray job.json -o t --dry-run; echo "rc=$?"
