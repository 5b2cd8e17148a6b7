$HOVOX info tests/data/bad/3mf_unknown_component.3mf
