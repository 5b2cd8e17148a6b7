$HOVOX layers --help
