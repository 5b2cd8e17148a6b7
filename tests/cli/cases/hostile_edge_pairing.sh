# issue 32 item 7: a million facets on one edge (the same triangle repeated; an OBJ face of a
# million corners on one vertex) are paired in linear time: before, pairing was quadratic in the
# facets sharing an edge (1M facets: about 7 minutes; the 2 MB face: hours). The timeout only
# catches a return of the quadratic rule; the run takes about a second.
awk 'BEGIN { print "v 0 0 0\nv 1 0 0\nv 0 1 0"; for (i = 0; i < 1000000; ++i) print "f 1 2 3" }' >"$TMP/same.obj"
timeout 60 $HOVOX info "$TMP/same.obj" >"$TMP/same.txt"
echo "rc=$?"
sed -n '3,4p;11,13p' "$TMP/same.txt"
awk 'BEGIN { printf "v 0 0 0\nv 1 0 0\nv 0 1 0\nf"; for (i = 0; i < 1000000; ++i) printf " 1"; print "" }' >"$TMP/corner.obj"
timeout 60 $HOVOX info "$TMP/corner.obj" >"$TMP/corner.txt"
echo "rc=$?"
sed -n '3,4p;11,14p' "$TMP/corner.txt"
