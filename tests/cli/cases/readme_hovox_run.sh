# issue 32.14: the README's `hovox run` examples run verbatim: the sh lines of its section, in a
# fresh directory without out/ (the samples make it), and every Lua block of the README
root=$(pwd)
mkdir -p "$TMP/bin" "$TMP/work" && ln -s "$HOVOX" "$TMP/bin/hovox" && ln -s "$root/samples" "$TMP/work/samples" || exit 1
cd "$TMP/work" || exit 1
printf 'local f = assert(io.open(arg[1] .. "/theirs.txt", "w"))\nf:write("written by their script\\n")\nf:close()\n' >their_script.lua
awk '/^### `hovox run /{s=1} s && /^```sh$/{f=1; next} f && /^```$/{exit} f' "$root/README.md" >run_examples.sh
while IFS= read -r line; do
    echo "\$ ${line%%#*}" | sed 's/ *$//'
    PATH="$TMP/bin:$PATH" sh -c "$line" >log.txt 2>&1
    rc=$?
    echo "rc=$rc"
    [ "$rc" = 0 ] || cat log.txt
done <run_examples.sh
ls out | sort
awk '/^```lua$/{f=1; n++; next} /^```$/{f=0} f {print > ("block" n ".lua")}' "$root/README.md"
for b in block*.lua; do
    echo "\$ hovox run $b lua_out/$b"
    $HOVOX run "$b" "lua_out/$b"; echo "rc=$?"
    ls "lua_out/$b"
done
