# issue 19, findings 1 and 4: option tables with metatables are refused before any script code
# runs; objects freed by a grading callback, a finalizer or the script raise errors, never crash
$HOVOX run --sandbox --output-dir "$TMP" tests/lua/scripts/hostile_free_in_use.lua "$TMP"; echo "rc=$?"
ls /tmp/hovox-escape.png 2>&1 | sed 's/^ls: //'
