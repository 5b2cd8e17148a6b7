# a tetrahedron with one face missing: open polylines are reported (--close-gap 0), or closed
# by the default gap rule (2 mm)
cat > "$TMP/open.stl" <<'STL'
solid open
facet normal 0 0 -1
outer loop
vertex 0 0 0
vertex 0 1 0
vertex 1 0 0
endloop
endfacet
facet normal 0 -1 0
outer loop
vertex 0 0 0
vertex 1 0 0
vertex 0 0 1
endloop
endfacet
facet normal -1 0 0
outer loop
vertex 0 0 0
vertex 0 0 1
vertex 0 1 0
endloop
endfacet
endsolid open
STL
$HOVOX contours "$TMP/open.stl" --layer-height 0.5 --close-gap 0 -o "$TMP/open.cli" && grep POLYLINE "$TMP/open.cli" &&
$HOVOX contours "$TMP/open.stl" --layer-height 0.5 --json
