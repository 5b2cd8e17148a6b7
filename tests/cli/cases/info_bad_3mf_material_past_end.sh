$HOVOX info tests/data/bad/3mf_material_past_end.3mf
