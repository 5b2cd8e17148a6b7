$HOVOX probe --help
