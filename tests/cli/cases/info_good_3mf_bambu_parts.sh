# Bambu Studio and OrcaSlicer make each volume of an object a mesh object (in
# /3D/Objects/object_1.model) that a component of the object places, and type them in
# Metadata/model_settings.config: <part id="the component's objectid" subtype="normal_part",
# "modifier_part", "negative_part", "support_blocker" or "support_enforcer"> (the package as
# tests/data/make/mesh_formats.py writes it after Bambu Studio 1.9's layout). Only normal parts
# are printed: the independent reading (zipfile + ElementTree + numpy, the config's rule) gives
# 12 facets, volume 4000, bbox (50, 60, 0) to (70, 80, 10). Before, hovox read the modifier and
# the support blocker as parts: 36 facets, volume 7875, bbox to (80, 80, 20)
$HOVOX info tests/data/good/3mf_bambu_parts.3mf
