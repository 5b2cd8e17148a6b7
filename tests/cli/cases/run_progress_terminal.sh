# issue 32.19: hovox run draws the library's progress bar on a terminal (each stage to 100%, once),
# none with -q, and none when stderr is not a terminal
cd "$TMP" || exit 1
printf 'local m = hovox.voxelize(hovox.generate.sphere{}, {dims = 64})\nprint("voxels", m:voxels())\n' >p.lua
bars() { tr '\r' '\n' | grep '100%' | sed 's/  */ /g' | sort -u; }
echo "terminal:"
script -qec "$HOVOX run p.lua" /dev/null | bars
echo "terminal, -q:"
script -qec "$HOVOX run -q p.lua" /dev/null | bars
echo "piped:"
$HOVOX run p.lua 2>&1 | tr -d '\r'
