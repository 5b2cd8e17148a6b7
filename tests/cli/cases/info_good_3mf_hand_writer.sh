# A hand writer's package (tests/data/make/mesh_formats.py): streamed with data descriptors and
# ZIP64 fields, a byte order mark, CRLF, the core namespace on a prefix, single-quoted attributes in
# another order, coordinates padded with white space (' 10 ': an ST_Number collapses it, 3MF Core
# 2.3.4; before, "x is not a finite number"), a transform over four lines. The independent reading
# (zipfile + ElementTree + numpy, from the spec): 12 facets, volume 240, area 248, bbox (14, 5, 1) to
# (20, 15, 5)
$HOVOX info tests/data/good/3mf_hand_writer.3mf
