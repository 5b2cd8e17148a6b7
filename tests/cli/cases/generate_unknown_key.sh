# a parameter the shape does not have, a shape there is not: exit 2 naming what there is
$HOVOX generate sphere radus=3 -o "$TMP/s.stl"; echo "rc=$?"
# an unknown shape is told the shapes there are (the same message in Python: test_errors.py)
$HOVOX generate blob -o "$TMP/s.stl"; echo "rc=$?"
