$HOVOX render model.vdb --step 0 -o out.png
