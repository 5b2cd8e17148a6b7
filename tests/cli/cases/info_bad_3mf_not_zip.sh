$HOVOX info tests/data/bad/3mf_not_zip.3mf
