# issue 19.8 (and 12): memory is planned before it is taken: a script over its memory limit
# stops with its line (exit 3), a render image over --max-memory is refused (exit 3)
printf 'local t = {}\nfor i = 1, 1e9 do t[i] = i end\n' >"$TMP/grow.lua"
$HOVOX run --max-memory 32M "$TMP/grow.lua"; echo "rc=$?"
$HOVOX render tests/data/models/linear2.vdb --size 8000x8000 -o "$TMP/x.png" --max-memory 100M; echo "rc=$?"
ls "$TMP"
