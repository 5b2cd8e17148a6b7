$HOVOX info tests/data/bad/3mf_missing_material.3mf
