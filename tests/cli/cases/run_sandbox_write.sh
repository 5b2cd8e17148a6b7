$HOVOX run --sandbox --output-dir "$TMP" tests/lua/scripts/sandbox_write.lua "$TMP"; ls "$TMP"
