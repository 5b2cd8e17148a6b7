# the scan bindings (hovox.scan_info, hovox.voxelize_scan) under attack: option tables and label lists
# with metatables, absurd shapes and sizes, lying and hostile files, a profile that is no profile,
# NUL bytes in paths; every attempt refused with a message or harmless, the script ends normally
mkdir -p "$TMP/out"
$HOVOX run --sandbox --output-dir "$TMP/out" --max-time 60 tests/lua/scripts/hostile_scan_bindings.lua "$TMP/out"
echo "rc=$?"
