# issue 29: an OBJ whose library gives a colour (Kd) and a JPEG texture (map_Kd) at the faces' vt
# coordinates: info lists the materials' colours and the texture with the facets that use it; then
# the texture missing or not a picture: one message each, exit 1; a library that is not there
# leaves the materials names only (OBJ files travel without theirs)
cp tests/fuzz/corpus/texture/flat.jpg "$TMP/wood.jpg"
printf 'newmtl wood\nKd 0.8 0.6 0.4\nmap_Kd wood.jpg\nnewmtl red\nKd 1 0 0\n' > "$TMP/cube.mtl"
printf 'mtllib cube.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl wood\nf 1/1 4/2 3/3 2/4\nf 5/1 6/2 7/3 8/4\nusemtl red\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n' > "$TMP/cube.obj"
$HOVOX info "$TMP/cube.obj" | sed -n '/materials/,$p'
rm "$TMP/wood.jpg"
$HOVOX info "$TMP/cube.obj"
echo "rc=$?"
printf 'not a picture' > "$TMP/wood.jpg"
$HOVOX info "$TMP/cube.obj"
echo "rc=$?"
rm "$TMP/cube.mtl"
$HOVOX info "$TMP/cube.obj" | sed -n '/materials/,/textures/p'
echo "rc=$?"
