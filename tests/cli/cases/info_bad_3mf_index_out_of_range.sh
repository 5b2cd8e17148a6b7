$HOVOX info tests/data/bad/3mf_index_out_of_range.3mf
