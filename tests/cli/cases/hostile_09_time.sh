# issue 19.9: Ctrl-C stops a script in a loop (exit 130), a time limit too (exit 3), and an
# absurd render step is a usage error
printf 'while true do end\n' >"$TMP/loop.lua"
timeout --preserve-status -s INT 1 $HOVOX run "$TMP/loop.lua"; echo "rc=$?"
$HOVOX run --max-time 0.5 "$TMP/loop.lua"; echo "rc=$?"
$HOVOX render tests/data/models/linear2.vdb -o "$TMP/x.png" --step 1e-9; echo "rc=$?"
