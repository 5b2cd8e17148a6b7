$HOVOX info --json tests/data/good/3mf_items_inch.3mf
