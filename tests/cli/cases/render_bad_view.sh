$HOVOX render model.vdb --view diagonal -o out.png
