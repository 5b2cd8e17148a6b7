# issue 27 item 2: Lua's mesh:layers{...} is `hovox layers PART.3mf -o DIR` in one step: the same
# files (layers and manifest) for core_in_shell.3mf with its core in Agilus30Black. Under
# --sandbox the stack's directory is checked where it is written: outside the output directory
# it is refused (exit 1, nothing written).
cp "$SHARED/good/core_in_shell.3mf" "$TMP/cis.3mf"
cd "$TMP" || exit 1
$HOVOX layers cis.3mf -o cli --layers 180:186 --material core=Agilus30Black | grep '^wrote'
cat >one.lua <<'LUA'
local r = hovox.load_mesh("cis.3mf"):layers{dir = arg[1], layers = {180, 186}, materials = {core = "Agilus30Black"}}
print(r.layers, r.first, r.last, r.object_pixels)
LUA
$HOVOX run one.lua lua
echo "rc=$?"
diff -r cli lua && echo "the same files"
mkdir out
$HOVOX run --sandbox --output-dir out one.lua elsewhere; echo "rc=$?"
ls
