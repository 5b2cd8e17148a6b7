# The same bad value given to the CLI and to Lua gets the same refusal: both print the
# library's message, and only the spelling of the option differs (--layer-height, layer_height).
# Each line: the CLI's message and Lua's, reduced to the message with options spelt as keys;
# "differ" fails the case.
M=tests/data/models/linear2.vdb
$HOVOX generate box -o "$TMP/b.stl" >/dev/null
cat >"$TMP/t.lua" <<'EOF'
local m, mesh = hovox.load(arg[1]), hovox.load_mesh(arg[2])
local out = arg[3]
local cases = {
    function() m:render{path = out .. "/x.png", step = 5} end,
    function() m:render{path = out .. "/x.png", fov = 180} end,
    function() m:render{path = out .. "/x.png", density = -1} end,
    function() m:render{path = out .. "/x.png", background = "nope"} end,
    function() m:layers{mesh = mesh, dir = out .. "/s", mode = "gray"} end,
    function() m:layers{mesh = mesh, dir = out .. "/s", seed = -2} end,
    function() m:layers{mesh = mesh, dir = out .. "/s", layer_height = 0} end,
    function() hovox.voxelize(mesh, {adjacency = 7}) end,
    function() m:export{path = out .. "/x.vtu", coarsen = 0} end,
    function() hovox.contours(mesh, {layer_height = 0}) end,
    function() m:profile{from = {0, 0, 0}, to = {1, 1, 1}, samples = 1} end,
    function() hovox.generate.sphere{radius = -1} end,
}
for _, c in ipairs(cases) do
    local ok, err = pcall(c)
    print(ok and "accepted" or (tostring(err):match("%((.*)%)$") or tostring(err)))
end
EOF
cli() { "$HOVOX" "$@" 2>&1 >/dev/null | sed -e "s/^hovox [a-z]*: //" -e "s/ (see 'hovox [a-z]* --help')$//" \
    -e 's/--\([a-z]*\)-\([a-z]*\)/\1_\2/g' -e 's/--\([a-z]*\)/\1/g' | sed 's/^$/accepted/'; }
{
    cli render "$M" -o "$TMP/x.png" --step 5
    cli render "$M" -o "$TMP/x.png" --fov 180
    cli render "$M" -o "$TMP/x.png" --density -1
    cli render "$M" -o "$TMP/x.png" --background nope
    cli layers "$M" --mesh "$TMP/b.stl" -o "$TMP/s" --mode gray
    cli layers "$M" --mesh "$TMP/b.stl" -o "$TMP/s" --seed -2
    cli layers "$M" --mesh "$TMP/b.stl" -o "$TMP/s" --layer-height 0
    cli voxelize "$TMP/b.stl" -o "$TMP/v.vdb" --adjacency 7
    cli export "$M" -o "$TMP/x.vtu" --coarsen 0
    cli contours "$TMP/b.stl" -o "$TMP/c.svg" --layer-height 0
    cli profile "$M" --from 0,0,0 --to 1,1,1 --samples 1 -o "$TMP/p.csv"
    cli generate sphere radius=-1 -o "$TMP/s.stl"
} >"$TMP/cli.txt"
"$HOVOX" run "$TMP/t.lua" "$M" "$TMP/b.stl" "$TMP" >"$TMP/lua.txt"
paste -d '\n' "$TMP/cli.txt" "$TMP/lua.txt" | paste - - | while IFS="$(printf '\t')" read -r a b; do
    if [ "$a" = "$b" ]; then echo "same     $a"; else echo "differ   cli: $a | lua: $b"; fi
done
