$HOVOX info tests/data/good/part.step
