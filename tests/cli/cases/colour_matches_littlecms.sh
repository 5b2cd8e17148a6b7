# issue 29: the colour map's fractions against Pillow's ImageCms (LittleCMS called independently)
# for 125 colours across the sRGB cube and three with alpha, with the default profile perceptual
# and relative, and with another CMYK profile (Ghostscript's ps_cmyk.icc, which has perceptual tables only;
# another intent is refused: see colour_cmd)
/usr/bin/python3 tests/colour/check_littlecms.py $HOVOX &&
/usr/bin/python3 tests/colour/check_littlecms.py $HOVOX --intent relative &&
/usr/bin/python3 tests/colour/check_littlecms.py $HOVOX --icc /usr/share/color/icc/ghostscript/ps_cmyk.icc
echo "rc=$?"
