# --bits is 8 or 16
$HOVOX export "$TMP/m.vdb" -o "$TMP/m.3mf" --volumetric --bits 12
