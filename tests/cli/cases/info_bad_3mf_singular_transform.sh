$HOVOX info tests/data/bad/3mf_singular_transform.3mf
