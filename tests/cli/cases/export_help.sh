$HOVOX export --help
