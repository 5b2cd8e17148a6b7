# issue 19.8 (and 12): memory is planned before it is taken: a script over its memory limit
# stops with one message (exit 3), a render image over --max-memory is refused (exit 3)
printf 'local t = {}\nfor i = 1, 1e9 do t[i] = i end\n' >"$TMP/grow.lua"
# the limit can trip inside a C call of the interpreter (a table resize) where the script's
# line is not known: the message then names the script alone, so the line is not pinned
msg=$($HOVOX run --max-memory 32M "$TMP/grow.lua" 2>&1); rc=$?
printf '%s\n' "$msg" | sed 's/grow\.lua:2: /grow.lua: /' >&2; echo "rc=$rc"
$HOVOX render tests/data/models/linear2.vdb --size 8000x8000 -o "$TMP/x.png" --max-memory 100M; echo "rc=$?"
ls "$TMP"
