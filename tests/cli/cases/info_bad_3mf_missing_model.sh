$HOVOX info tests/data/bad/3mf_missing_model.3mf
