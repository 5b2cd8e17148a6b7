$HOVOX profile --help
