$HOVOX info tests/data/bad/3mf_cyclic_component.3mf
