# this round's Lua bindings under attack (issue 32's sandbox rules): every attempt is refused with
# a message or is harmless, nothing is written outside the output directory or through a symlink
# in it, and a loop that catches its own errors still ends at --max-time (exit 3)
mkdir -p "$TMP/out" "$TMP/escape"
ln -s "$TMP/escape" "$TMP/out/link"
$HOVOX run --sandbox --output-dir "$TMP/out" --max-time 60 tests/lua/scripts/hostile_round3_bindings.lua "$TMP/out"
echo "rc=$?"
ls -A "$TMP/escape" /tmp/hovox-escape-stack 2>&1 | sed 's/^ls: //'
printf 'while true do pcall(function() while true do end end) end\n' >"$TMP/loop.lua"
$HOVOX run --sandbox --output-dir "$TMP/out" --max-time 2 "$TMP/loop.lua"
echo "rc=$?"
