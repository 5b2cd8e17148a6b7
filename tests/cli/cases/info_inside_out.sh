# issue 27 item 4: a closed body wound inside out (negative volume) is named in info, as a
# warning and in the JSON; a body wound outward beside it is not
cat >"$TMP/in.stl" <<'STL'
solid inward
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 10 0 0
vertex 0 10 0
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0 0 10
vertex 10 0 0
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0 10 0
vertex 0 0 10
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 10 0 0
vertex 0 0 10
vertex 0 10 0
endloop
endfacet
endsolid inward
STL
"$HOVOX" info "$TMP/in.stl"
echo "rc $?"
cat >"$TMP/two.obj" <<'OBJ'
v 0 0 0
v 10 0 0
v 0 10 0
v 0 0 10
v 20 0 0
v 30 0 0
v 20 10 0
v 20 0 10
o outward
f 1 3 2
f 1 2 4
f 1 4 3
f 2 3 4
o inward
f 5 6 7
f 5 8 6
f 5 7 8
f 6 8 7
OBJ
"$HOVOX" info "$TMP/two.obj"
echo "rc $?"
"$HOVOX" info --json "$TMP/two.obj" | /usr/bin/python3 -c 'import json,sys; d=json.load(sys.stdin); print(d["inside_out"], [(b["name"], b["inside_out"], b["volume"]) for b in d["bodies"]])'
