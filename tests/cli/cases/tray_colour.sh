# issue 29 (tray colour): a mesh part that carries colour (a texture, vertex colours, an OBJ's MTL
# colours) and no material is painted in the tray as `layers MESH` paints it. The six-colour cube:
# each face's skin in the tray holds the same resin shares as the layers stack within 0.01, and
# Pillow ImageCms's fractions of the face's colour within 0.02; the part's manifest entry carries
# the colour's dE2000 (tests/colour/check_tray_colour.py). Then the part keys in a job file
# (colour_depth, core; icc relative to the job file), and refusals: one message, exit 1 or 2,
# nothing written.
/usr/bin/python3 tests/colour/check_tray_colour.py "$HOVOX" "$TMP"
echo "rc=$?"
cd "$TMP"
rm -rf layers tray
printf '{"icc": "cmyk.icc", "parts": [{"mesh": "cube.obj", "at": [40, 30], "colour_depth": 0.5, "core": "#808080"}]}\n' >j.json
cp /usr/share/color/icc/ghostscript/default_cmyk.icc cmyk.icc
"$HOVOX" tray "$TMP/j.json" -o out --layers 30:32
echo "rc=$?"
/usr/bin/python3 -c "
import json, sys
p = json.load(open('out/manifest.json'))['parts'][0]
print(sorted(p['materials']), p['colour']['icc'], p['colour']['skin_voxels'])"
rm -rf out
echo 'not a profile' >bad.icc
"$HOVOX" tray --part cube.obj@40,30 --icc bad.icc -o out; echo "rc=$?"
"$HOVOX" tray --part cube.obj:VeroClear@40,30 --core Agilus30 -o out; echo "rc=$?"
"$HOVOX" generate box max=4,4,4 -o plain.stl >/dev/null
"$HOVOX" tray --part plain.stl@40,30 --colour-depth 1 -o out; echo "rc=$?"
"$HOVOX" tray --colour-depth 1 -o out; echo "rc=$?"
ls
