$HOVOX info tests/data/bad/3mf_unknown_unit.3mf
