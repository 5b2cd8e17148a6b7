$HOVOX render model.vdb --size 0x10 -o out.png
