# issue 19.10: voxels too small for the lattice are refused up front (exit 2), not by OpenVDB
$HOVOX generate box -o "$TMP/b.stl"
$HOVOX voxelize "$TMP/b.stl" -o "$TMP/m.vdb" --voxel-size 1e-6; echo "rc=$?"
$HOVOX voxelize "$TMP/b.stl" -o "$TMP/m.vdb" --voxel-size 1e-5,1,1; echo "rc=$?"
