# A part and the support it stands on, one object of components (3MF Core 4.1: a "support" object
# SHOULD be a component of the object it supports; a manufacturing device MUST NOT fill it). Before,
# the support tetrahedron was read as part of the body (16 facets, volume 1004.5, bbox to x 15) and
# filled; the independent reading skips it, as hovox skips an item of a support object: 12 facets,
# volume 1000, bbox (0, 0, 0) to (10, 10, 10)
$HOVOX info tests/data/good/3mf_support_component.3mf
