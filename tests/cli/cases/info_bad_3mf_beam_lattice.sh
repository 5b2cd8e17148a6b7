$HOVOX info tests/data/bad/3mf_beam_lattice.3mf
