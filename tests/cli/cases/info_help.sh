$HOVOX info --help
