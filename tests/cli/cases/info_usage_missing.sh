$HOVOX info
