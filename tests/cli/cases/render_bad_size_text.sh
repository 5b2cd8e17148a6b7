$HOVOX render model.vdb --size 640 -o out.png
