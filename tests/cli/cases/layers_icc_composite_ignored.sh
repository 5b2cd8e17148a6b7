# smsg item 2: `layers --icc/--intent/--resins` on a 3MF package whose <v:composite> gives the
# fractions: one warning saying why they have no effect, and the same layers as without them; a
# package's colour without a composite takes them with no warning (read_3mf_colour_options).
P=/usr/share/color/icc/ghostscript/ps_cmyk.icc
R=VeroCyan-V,VeroMagenta-V,VeroYellow-V,VeroBlackPlus,Agilus30White,VeroClear
m=tests/data/good/volumetric_box.3mf
$HOVOX layers $m -o "$TMP/plain" -q; echo "rc=$?"
$HOVOX layers $m -o "$TMP/icc" -q --icc $P; echo "rc=$?"
$HOVOX layers $m -o "$TMP/all" -q --icc $P --intent relative --resins $R; echo "rc=$?"
for d in icc all; do diff -r "$TMP/plain" "$TMP/$d" && echo "$d: the same stack (layers and manifest)"; done
/usr/bin/python3 tests/colour/colour_package.py write "$TMP" || exit 9
$HOVOX layers "$TMP/turned.3mf" -o "$TMP/turned" --layers 100:101 -q --icc $P; echo "rc=$?"
