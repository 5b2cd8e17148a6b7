# issue 32 item 8: no output may be a file the same command reads, through any path, symbolic link
# or hard link: each attempt is refused with one message naming both, the input is left as it
# was and nothing is written. Before, each of these replaced its input.
set -u
$HOVOX generate box -o "$TMP/b.stl" >/dev/null
$HOVOX voxelize "$TMP/b.stl" --voxel-size 2 -o "$TMP/m.vdb"
$HOVOX grade "$TMP/m.vdb" -o "$TMP/g.vdb" --materials VeroCyan-V,VeroMagenta-V --frf plane:0,0,0:0,0,1 \
    --ranges 0,5,0 --ms 1,0 --me 0,1 -q
cd "$TMP"
sum() { cksum "$@" | awk '{print $1, $3}'; }
sum b.stl g.vdb >before
try() { "$@" -q >/dev/null; echo "rc=$?"; }
# a graded model as its own field feature
try $HOVOX grade m.vdb -o g.vdb --materials A,B --frf field:g.vdb:material.VeroCyan-V --ranges 0,1,0 --ms 1,0 --me 0,1
# a calibration table that is the output (a CSV named .vdb)
printf 't,youngs_modulus[MPa]\n0,1\n1,2\n' >c.vdb
try $HOVOX grade m.vdb -o c.vdb --materials A,B --frf plane:0,0,0:0,0,1 --ranges 0,5,0 --ms 1,0 --me 0,1 \
    --calibration c.vdb --property-grading youngs_modulus --ps 1.2MPa --pe 1.8MPa
# render onto its model, through a symbolic link and a hard link
ln -s g.vdb link.png
try $HOVOX render g.vdb -o link.png --size 16x16
ln g.vdb hard.png
try $HOVOX render g.vdb -o hard.png --size 16x16
# an export over its linearization table
printf 'fraction.VeroCyan-V,youngs_modulus[Pa]\n0,1\n1,2\n' >t.vti
try $HOVOX export g.vdb -o t.vti --linearize youngs_modulus=t.vti
# a tray writing its placed parts over a part's mesh, and its GCVF zip over a part's model
try $HOVOX tray -o stack --part g.vdb,b.stl@100,100 --stl b.stl --force --layers 0:1
cp g.vdb gz.zip
try $HOVOX tray -o stack2 --part gz.zip,b.stl@100,100 --gcvf gz.zip --force --layers 0:1
# a stack directory holding the tray's own model
mkdir -p held && cp g.vdb held/g.vdb
try $HOVOX tray -o held --part held/g.vdb,b.stl@100,100 --force --layers 0:1
sum b.stl g.vdb | cmp -s - before && echo "inputs unchanged"
cat c.vdb t.vti | wc -l
ls -a . held
