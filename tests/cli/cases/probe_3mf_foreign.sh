# a 3MF Volumetric package from another producer (tests/data/make_3mf.py): base material names become
# hovox names, the composite's channels the fractions
$HOVOX probe tests/data/good/volumetric_box.3mf 10.5,20.5,0.5 13.5,22.5,1.5 11.5,21,1 12,21.5,1 9,20,0
