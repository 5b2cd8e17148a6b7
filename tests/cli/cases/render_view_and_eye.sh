$HOVOX render model.vdb --view top --eye 1,2,3 -o out.png
