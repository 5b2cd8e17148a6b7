# issue 29 item 2: an assembly painted by body, after the 3MF specifications (README "A coloured mesh
# straight to a stack or a tray"). badge.3mf (tests/colour/colour_assembly.py, written by Python): a
# plate of Agilus30Black (a resin), a badge on it in a colour group's #C01010, a grip of "PLA Blue"
# (a base material that names no resin). Unasked, the colour group's body is painted and the others
# print in their materials; with --colour-depth the grip's displaycolor paints it too; the plate
# stays Agilus30Black either way (every pixel of it). Per box the resin shares of a layer read by
# Pillow (tests/colour/check_assembly.py): the skins carry `hovox colour`'s fractions of the two
# colours within 0.02, the cores the white resin. A tray paints the part alike (--colour-depth after
# its --part); an assembly of resins alone with --colour-depth: one message, exit 1, nothing written.
/usr/bin/python3 tests/colour/colour_assembly.py "$TMP" >/dev/null || exit 9
C="/usr/bin/python3 tests/colour/check_assembly.py"
$HOVOX colour '#c01010' '#2050c0' | tail -2
$HOVOX layers "$TMP/badge.3mf" -o "$TMP/a" --layers 74:75 | sed -n '/^voxels/p;/^bodies/p;/^colour/p'
$C "$TMP/a" 74 base=0.5,0.5,19.5,19.5 grip=22.5,0.5,29.5,19.5
$HOVOX layers "$TMP/badge.3mf" -o "$TMP/b" --layers 222:223 | sed -n '/^colour/p'
$C "$TMP/b" 222 badgeskin=4.1,4.1,4.6,15.9 badgecore=6,6,14,14
$HOVOX layers "$TMP/badge.3mf" -o "$TMP/c" --layers 74:75 --colour-depth 1 | sed -n '/^bodies/p;/^colour/p'
$C "$TMP/c" 74 base=0.5,0.5,19.5,19.5 gripskin=22.1,0.1,22.6,19.9 gripcore=24,2,28,18
$HOVOX tray --part "$TMP/badge.3mf@60,60" --colour-depth 1 -o "$TMP/t" --layers 74:75 | sed -n '/^plate/p;/^colour/p'
/usr/bin/python3 -c "
import json, sys
p = json.load(open(sys.argv[1]))['parts'][0]
print(sorted(p['materials']), p['colour']['skin_voxels'])" "$TMP/t/manifest.json"
$HOVOX layers "$TMP/resins.3mf" -o "$TMP/x" --colour-depth 1; echo "rc=$?"
ls "$TMP"
