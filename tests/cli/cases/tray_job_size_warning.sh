# issue 27 item 3: a job file's part whose mesh, as placed, is under 1 mm or fits no orientation of
# the build volume is warned about naming the likely unit and the part's key (the one rule of
# voxelize, layers and --part: hv_placement_size_warning, applied where the tray reads its parts);
# with "unit": "m" the same part is 200 mm across and says nothing. A part too large for the J750
# (600 mm long) is warned about too, before the tray refuses it.
$HOVOX generate box min=0,0,0 max=0.2,0.1,0.05 -o "$TMP/tiny.stl" >/dev/null
$HOVOX generate box size=600,20,10 -o "$TMP/long.stl" >/dev/null
cat >"$TMP/job.json" <<'JOB'
{"mode": "mask",
 "parts": [{"mesh": "tiny.stl", "material": "VeroCyan-V", "at": [100, 100]},
           {"mesh": "tiny.stl", "material": "VeroCyan-V", "at": [300, 100], "unit": "m"}]}
JOB
$HOVOX tray "$TMP/job.json" --dry-run | grep '^parts'
echo "rc=$?"
printf '{"mode": "mask", "parts": [{"mesh": "long.stl", "material": "VeroCyan-V"}]}\n' >"$TMP/long.json"
$HOVOX tray "$TMP/long.json" --dry-run; echo "rc=$?"
