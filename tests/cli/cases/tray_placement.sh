# issue 27 item 3: tray parts are placed like voxelize's meshes: on the command line the placement
# options after a --part place it, in a job file they are the part's keys. A 30 x 20 x 10 box
# stood up (Y-up) is 20 mm tall (741 J750 layers) and turned 90 degrees, 10 x 30 mm on the plate.
$HOVOX generate box size=30,20,10 -o "$TMP/box.stl" >/dev/null
$HOVOX tray --part "$TMP/box.stl:VeroCyan-V@100,100" --up y --rotate z:90 \
    --part "$TMP/box.stl:VeroCyan-V@200,100" --mode mask -o "$TMP/a"
grep -o '"placement": "[^"]*"\|"box_mm": \[[^]]*\]' "$TMP/a/manifest.json"
cat >"$TMP/job.json" <<'JOB'
{"schema": 1, "profile": "j750", "mode": "mask",
 "parts": [{"mesh": "box.stl", "material": "VeroCyan-V", "at": [100, 100], "up": "y", "rotate": ["z:90"]},
           {"mesh": "box.stl", "material": "VeroCyan-V", "at": [200, 100], "scale": [0.5, 0.5, 2]}]}
JOB
$HOVOX tray "$TMP/job.json" -o "$TMP/b"
grep -o '"placement": "[^"]*"\|"box_mm": \[[^]]*\]' "$TMP/b/manifest.json"
# refused: a placement before any --part, one given twice for a part, a bad key value in a job
$HOVOX tray --rotate z:90 --part "$TMP/box.stl:VeroCyan-V" -o "$TMP/c"; echo "rc $?"
$HOVOX tray --part "$TMP/box.stl:VeroCyan-V" --unit cm --unit m -o "$TMP/c"; echo "rc $?"
sed 's/"up": "y"/"up": "x"/' "$TMP/job.json" >"$TMP/bad.json"
$HOVOX tray "$TMP/bad.json" -o "$TMP/c"; echo "rc $?"
ls "$TMP"
