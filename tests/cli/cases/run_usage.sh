$HOVOX run
