# a damaged 3MF package (tests/data/make_3mf.py): one message naming the file and the place, exit 1
$HOVOX probe tests/data/bad/3mf_no_model.3mf 10.5,20.5,0.5
