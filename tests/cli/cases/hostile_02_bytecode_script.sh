# issue 19.2: a precompiled chunk as the sandboxed script itself is refused (Lua does not verify
# bytecode), without running any of it; outside the sandbox it still runs
cat >"$TMP/make.lua" <<'LUA'
local f = assert(io.open(arg[1], "wb"))
f:write(string.dump(load("print('bytecode ran')")))
f:close()
LUA
mkdir "$TMP/out"
$HOVOX run "$TMP/make.lua" "$TMP/b.luac" && $HOVOX run "$TMP/b.luac"
$HOVOX run --sandbox --output-dir "$TMP/out" "$TMP/b.luac"; echo "rc=$?"
