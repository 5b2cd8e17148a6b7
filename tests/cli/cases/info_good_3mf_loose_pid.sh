$HOVOX info tests/data/good/3mf_loose_pid.3mf
