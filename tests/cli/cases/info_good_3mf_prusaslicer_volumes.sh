# PrusaSlicer keeps all the volumes of an object in its one <mesh> and says in
# Metadata/Slic3r_PE_model.config which triangles are a part and which a settings modifier, a
# support blocker or enforcer or a negative volume (tests/data/make/mesh_formats.py writes the
# package as PrusaSlicer 2.5 does). PrusaSlicer 2.5 itself (prusa-slicer --export-stl, read by
# admesh) gives the part alone: 12 facets, volume 4000, x 100..120, z 0..10. Before, hovox read all
# three volumes as one solid body 'body 1': 36 facets, volume 9250, bbox to (130, 120, 20). The
# body takes the name the config gives the object; the stack holds the part only
$HOVOX info tests/data/good/3mf_prusaslicer_volumes.3mf
$HOVOX layers tests/data/good/3mf_prusaslicer_volumes.3mf --material bracket.stl=VeroWhite-V --dpi 50,50 \
    --layer-height 1 -o "$TMP/s" -q && grep -E '"bbox_mm"|"layers_total"' "$TMP/s/manifest.json"
