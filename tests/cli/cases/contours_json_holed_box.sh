# per-layer statistics; the SVG parses as XML
$HOVOX generate holed-box -o "$TMP/hb.stl" &&
$HOVOX contours "$TMP/hb.stl" --layer-height 5 --json -o "$TMP/hb.svg" &&
xmllint --noout "$TMP/hb.svg" && grep -c '<g id="layer-' "$TMP/hb.svg"
