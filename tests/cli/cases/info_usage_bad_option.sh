$HOVOX info --bogus x.stl
