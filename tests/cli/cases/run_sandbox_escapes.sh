$HOVOX run --sandbox --output-dir "$TMP" tests/lua/scripts/sandbox_escapes.lua "$TMP"; echo "rc=$?"; ls "$TMP"
$HOVOX run --sandbox --output-dir "$TMP/none" tests/lua/scripts/sandbox_escapes.lua "$TMP"; echo "rc=$?"
