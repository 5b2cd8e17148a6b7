# Copies in a row (issue 32 item 13): `--part pin.stl:VeroPureWhite@40,40x4` was always refused
# (copies pitched at width + spacing, the footprint check asked for more), `--spacing 0` too
# ("closer than 0 mm"). Copies are pitched at the width plus the spacing on the 0.5 mm footprint
# grid; parts closer than the spacing, or overlapping at spacing 0, are still refused.
cd "$TMP"
"$HOVOX" generate box max=6,6,0.5 -o pin.stl >/dev/null
"$HOVOX" generate box max=6.2,4,0.5 -o odd.stl >/dev/null
"$HOVOX" tray -o t --part pin.stl:VeroPureWhite@40,40x4 --dry-run >plan; echo "rc=$?"; grep "^part " plan
"$HOVOX" tray -o t --part pin.stl:VeroPureWhite@40,40x4 --spacing 0 --dry-run >plan; echo "rc=$?"; grep "^part " plan
# a job file's copies without arrange; a width off the grid is pitched up to it (6.2 + 5 -> 11.5)
printf '{"parts": [{"mesh": "odd.stl", "material": "VeroPureWhite", "at": [40, 40], "copies": 3}]}\n' >j.json
"$HOVOX" tray j.json -o t --dry-run >plan; echo "rc=$?"; grep "^part " plan
"$HOVOX" tray -o t --part pin.stl:VeroPureWhite@40,40 --part pin.stl:VeroPureWhite@50,40 --dry-run; echo "rc=$?"
"$HOVOX" tray -o t --part pin.stl:VeroPureWhite@40,40 --part pin.stl:VeroPureWhite@45,40 --spacing 0 --dry-run; echo "rc=$?"
# the stack: four pins whose images do not meet
"$HOVOX" tray -o t --part pin.stl:VeroPureWhite@40,40x4 -q >/dev/null; echo "rc=$?"
/usr/bin/python3 - <<'PY'
import json
m = json.load(open("t/manifest.json"))
for p in m["parts"]:
    print(p["name"], p["copy"], p["at_mm"], p["image_px"])
PY
