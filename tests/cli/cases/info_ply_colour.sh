# issue 29: PLY vertex colours (red green blue alpha, uchar) are read as corner colours; a float
# colour outside [0, 1] (here the uchar 255 of a property declared float) is refused with the line and
# the vertex, exit 1
printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n0 0 1 255 255 255 128\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n' > "$TMP/tet.ply"
$HOVOX info "$TMP/tet.ply" | grep -E "format|facets|corner"
sed -e 's/uchar red/float red/' -e 's/^1 0 0 0 255 0 255$/1 0 0 2.5 255 0 255/' "$TMP/tet.ply" > "$TMP/bad.ply"
$HOVOX info "$TMP/bad.ply"
echo "rc=$?"
