$HOVOX render model.vdb --clip-box 0,0,0,1,1,0 -o out.png
