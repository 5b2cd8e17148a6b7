$HOVOX generate box -o /nonexistent-dir/box.stl
