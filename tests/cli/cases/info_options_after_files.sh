# options may follow the file names; a failure anywhere prints no partial report
$HOVOX info tests/data/good/bom_ascii.stl --json
echo "rc=$?"
$HOVOX info tests/data/good/bom_ascii.stl tests/data/bad/empty.stl
echo "rc=$?"
