$HOVOX frobnicate
