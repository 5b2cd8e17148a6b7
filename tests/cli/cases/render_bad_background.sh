$HOVOX render model.vdb --background '#12345' -o out.png
