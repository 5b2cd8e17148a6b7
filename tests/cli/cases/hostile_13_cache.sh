# issue 19, finding 13: a sandboxed run keeps the blue-noise tile in memory; nothing is written
# outside --output-dir, not even the cache
mkdir -p "$TMP/out" "$TMP/cache"
XDG_CACHE_HOME="$TMP/cache" HOME="$TMP/home" $HOVOX run --sandbox --output-dir "$TMP/out" \
    tests/lua/scripts/layers_small.lua "$TMP/out"; echo "rc=$?"
find "$TMP/cache" -type f | wc -l
test -e "$TMP/home" && echo "home written" || echo "home untouched"
ls "$TMP/out/stack" | wc -l
