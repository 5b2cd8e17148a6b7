ln -s /tmp/hovox-sandbox-link-target.stl "$TMP/link"
$HOVOX run --sandbox --output-dir "$TMP" tests/lua/scripts/sandbox_escapes.lua "$TMP"; echo "rc=$?"; ls "$TMP"
ls /tmp/hovox-sandbox-link-target.stl 2>&1 | sed 's/^ls: //'
$HOVOX run --sandbox --output-dir "$TMP/none" tests/lua/scripts/sandbox_escapes.lua "$TMP"; echo "rc=$?"
