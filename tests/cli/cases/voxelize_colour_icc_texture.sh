# issue 29 item 4: a texture's embedded ICC profile (PNG iCCP, JPEG APP2) is its colours' space:
# a cube textured by a flat Adobe RGB picture paints Pillow ImageCms's fractions of that colour
# through a98.icc within 0.01, not those of the same numbers read as sRGB
# (tests/colour/check_icc_texture.py). A picture that embeds a CMYK profile is refused: one
# message, exit 1, nothing written.
/usr/bin/python3 tests/colour/check_icc_texture.py "$HOVOX" "$TMP"
echo "rc=$?"
cd "$TMP"
/usr/bin/python3 -c "
from PIL import Image
Image.new('RGB', (8, 8), (120, 160, 200)).save('t.png', icc_profile=open('/usr/share/color/icc/ghostscript/default_cmyk.icc', 'rb').read())"
printf 'newmtl skin\nmap_Kd t.png\n' >t.mtl
rm -f *.vdb
"$HOVOX" voxelize t.obj --voxel-size 0.5 --colour-depth 1 -o bad.vdb; echo "rc=$?"
ls
