$HOVOX render model.vdb --clip 'x>>1' -o out.png
