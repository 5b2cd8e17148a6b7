# a text file that is not an ASCII STL is named as such, not as a truncated binary STL
$HOVOX info tests/data/bad/text_not_stl.stl
