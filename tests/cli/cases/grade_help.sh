$HOVOX grade --help
