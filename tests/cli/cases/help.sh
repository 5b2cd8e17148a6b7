$HOVOX --help
