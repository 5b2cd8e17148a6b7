# issue 29: `hovox colour`: fractions of the six resins for primaries, white, black, grey and a
# half-transparent red with the default profile; another resin map; refusals: a profile that is not
# ICC, an RGB profile, a missing one, a bad colour, five resins
$HOVOX colour '#ff0000' '#00ff00' '#0000ff' '#ffffff' '#000000' '#808080' '#ff000080'
$HOVOX colour 1,1,0 --resins 'C1, M1,Y1,K1,W1,Clear1' --intent relative
printf 'not a profile' > "$TMP/x.icc"
$HOVOX colour '#ff0000' --icc "$TMP/x.icc"
echo "rc=$?"
# a file of a profile's size without the signature, and a profile cut short (review item 2: one
# message each, file, what and value)
head -c 300 /dev/zero | tr '\0' 'x' > "$TMP/y.icc"
$HOVOX colour '#ff0000' --icc "$TMP/y.icc"
echo "rc=$?"
head -c 400 /usr/share/color/icc/ghostscript/ps_cmyk.icc > "$TMP/z.icc"
$HOVOX colour '#ff0000' --icc "$TMP/z.icc"
echo "rc=$?"
$HOVOX colour '#ff0000' --icc /usr/share/color/icc/ghostscript/srgb.icc
echo "rc=$?"
$HOVOX colour '#ff0000' --icc "$TMP/none.icc"
echo "rc=$?"
$HOVOX colour '#ff00'
echo "rc=$?"
$HOVOX colour '#ff0000' --resins a,b,c,d,e
echo "rc=$?"
$HOVOX colour '#ff0000' --intent vivid
echo "rc=$?"
$HOVOX colour '#ff0000' --icc /usr/share/color/icc/ghostscript/ps_cmyk.icc --intent saturation
echo "rc=$?"
