$HOVOX contours --help
