# issue 29 item 3: volume data with a <v:color> and no <v:composite> (as a colour printer's
# package holds it; here hovox's own package of a painted cube with the composite taken out) prints
# as a painted part: the colour's stack gives the voxels, the six colour resins of the default
# colour map their fractions (the white resin where hovox:colour.mask says no colour was asked
# for: the core), and `layers` reports the colour's dE2000 through that map
$HOVOX voxelize samples/colour_cube.obj --voxel-size 1 --colour-depth 1 --core Agilus30 -o "$TMP/c.vdb" >/dev/null || exit 9
$HOVOX export "$TMP/c.vdb" -o "$TMP/c.3mf" --volumetric -q >/dev/null || exit 9
/usr/bin/python3 tests/colour/colour_alone.py "$TMP/c.3mf" "$TMP/alone.3mf" || exit 9
$HOVOX probe "$TMP/alone.3mf" 5,5,0.5 5,5,5
$HOVOX layers "$TMP/alone.3mf" -o "$TMP/st" --dpi 254,254 --layer-height 0.1 | sed -n '/^material/,$p'
