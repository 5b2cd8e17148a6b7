# issue 29 item 3: a colour printer's package (tests/colour/colour_package.py, written by Python: a
# <v:color> and no <v:composite>, turned 30 degrees about z, so not axis-aligned) prints through the
# caller's colour map: `layers --icc --intent --resins` and a tray's (the tray's options, part
# MODEL,MESH; its targets within 1e-4 of layers', its pixels lie elsewhere), the same dE2000, the
# profile and resins named (the white role played by Agilus30White here). Voxels as fine as the
# image's finest step (2.75 mm here). python/tests/test_api.py checks every voxel's colour
# against the spec's sampling and its fractions against Pillow ImageCms. Refused: a profile that is
# not one (exit 1, nothing written); --icc for a .vdb model (exit 2: its colours were mapped).
/usr/bin/python3 tests/colour/colour_package.py write "$TMP" || exit 9
cd "$TMP" || exit 9
P=/usr/share/color/icc/ghostscript/ps_cmyk.icc
R=VeroCyan-V,VeroMagenta-V,VeroYellow-V,VeroBlackPlus,Agilus30White,VeroClear
$HOVOX layers turned.3mf -o default --layers 100:101 | sed -n '/^material/,/^colour/p'
$HOVOX layers turned.3mf -o ps --layers 100:101 --icc $P --resins $R | sed -n '/^material/,/^colour/p'
$HOVOX tray --part turned.3mf,turned.3mf@60,60 -o tray --layers 100:101 --icc $P --resins $R \
    | sed -n '/^colour/p'
/usr/bin/python3 -c "
import json
p = json.load(open('tray/manifest.json'))['parts'][0]
print(', '.join('%s %.6f' % (k, v['target']) for k, v in p['materials'].items()), p['colour']['skin_voxels'])"
$HOVOX layers turned.3mf -o bad --icc /etc/passwd; echo "rc=$?"
[ -e bad ] || echo "nothing written"
cd - >/dev/null || exit 9
$HOVOX voxelize samples/colour_cube.obj --voxel-size 1 -o "$TMP/c.vdb" -q || exit 9
$HOVOX layers "$TMP/c.vdb" -o "$TMP/v" --icc $P; echo "rc=$?"
