$HOVOX info --json tests/data/good/two_boxes.3mf
