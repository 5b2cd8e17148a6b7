# A model hovox 0.1.0 wrote (metadata documents without "schema") still probes, rebuilds its
# grading definition for --method direct, and its mesh record is read for the mesh check: the
# sphere it was voxelized from raises no warning, a smaller one does.
$HOVOX probe "$SHARED/models/legacy_graded.vdb" 4,4,4 &&
$HOVOX generate sphere radius=2.5 cx=4 cy=4 cz=4 segments=12 rings=6 -o "$TMP/s.stl" >/dev/null &&
$HOVOX generate sphere radius=1 cx=4 cy=4 cz=4 segments=12 rings=6 -o "$TMP/small.stl" >/dev/null &&
$HOVOX layers "$SHARED/models/legacy_graded.vdb" --mesh "$TMP/s.stl" -o "$TMP/direct" --method direct \
    --mode fractions --dpi 25.4,25.4 --layer-height 1 >/dev/null &&
grep -c '"index"' "$TMP/direct/manifest.json" &&
$HOVOX layers "$SHARED/models/legacy_graded.vdb" --mesh "$TMP/small.stl" -o "$TMP/other" --mode fractions \
    --dpi 25.4,25.4 --layer-height 1 --dry-run >/dev/null
