$HOVOX --version
