$HOVOX render model.vdb -o out.bmp
