# contours of an assembly read from OBJ: each body from its own facets, a part per body in the
# CLI file ($$LABEL/1,core and $$LABEL/2,shell; polylines carry their body's id), one path per
# body in the SVG (data-body), loops per body in --json
$HOVOX run tests/lua/scripts/assembly.lua "$TMP" &&
$HOVOX contours "$TMP/assembly.obj" --layer-height 2 -o "$TMP/a.cli" &&
cat "$TMP/a.cli" &&
$HOVOX contours "$TMP/assembly.obj" --layer-height 2 -o "$TMP/a.svg" --json &&
grep -c 'data-body="core"' "$TMP/a.svg"
echo "rc=$?"
