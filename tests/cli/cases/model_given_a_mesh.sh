# A mesh where a model goes is told it is a mesh, not "bad magic number"; Lua's hovox.load names
# hovox.load_mesh (Python's: python/tests/test_errors.py); a file that is neither keeps the magic.
# A model where a mesh goes is told it is an OpenVDB model (not "unsupported mesh format 'vdb'").
cd "$TMP"
"$HOVOX" generate box max=2,2,2 -o b.stl >/dev/null
"$HOVOX" probe b.stl 1,1,1; echo "rc=$?"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >t.obj
"$HOVOX" export t.obj -o t.vti; echo "rc=$?"
printf 'local m = hovox.load("b.stl")\n' >l.lua
"$HOVOX" run l.lua; echo "rc=$?"
printf 'local m = hovox.load("%s")\n' "$SHARED/good/two_boxes.3mf" >p.lua
"$HOVOX" run p.lua; echo "rc=$?"
printf 'print(hovox.load_mesh("b.stl"):report().facets)\n' >ok.lua
"$HOVOX" run ok.lua; echo "rc=$?"
echo hello >notes.txt
"$HOVOX" probe notes.txt 1,1,1; echo "rc=$?"
# and the other way: a model where a mesh goes
"$HOVOX" voxelize b.stl --voxel-size 0.5 -o b.vdb -q
"$HOVOX" voxelize b.vdb -o c.vdb; echo "rc=$?"
printf 'hovox.load_mesh("b.vdb")\n' >m.lua
"$HOVOX" run m.lua; echo "rc=$?"
