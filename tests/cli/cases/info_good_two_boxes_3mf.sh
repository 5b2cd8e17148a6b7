$HOVOX info tests/data/good/two_boxes.3mf
