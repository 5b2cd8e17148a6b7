$HOVOX info tests/data/bad/3mf_truncated_zip.3mf
