$HOVOX export "$TMP/m.vdb" -o "$TMP/m.vtk"
