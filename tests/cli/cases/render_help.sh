$HOVOX render --help
