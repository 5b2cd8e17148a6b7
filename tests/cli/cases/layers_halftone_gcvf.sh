# two materials graded along x over a 10 x 6 x 3 mm box, error diffusion, 100 x 50 dpi,
# 0.5 mm layers, with a GCVF zip; the summary, the archive listing and ConfigFile.xml
$HOVOX generate box sx=10 sy=6 sz=3 -o "$TMP/b.stl" &&
$HOVOX voxelize "$TMP/b.stl" --voxel-size 0.5 -o "$TMP/b.vdb" &&
$HOVOX grade "$TMP/b.vdb" -o "$TMP/g.vdb" --materials soft,hard --colors '#ff0000,#0000ff' \
    --frf plane:0,0,0:1,0,0 --ranges 0,10,0 --ms 1,0 --me 0,1 -q &&
$HOVOX layers "$TMP/g.vdb" --mesh "$TMP/b.stl" -o "$TMP/stack" --dpi 100,50 --layer-height 0.5 \
    --halftone error --seed 7 --background '#ffffff' --gcvf "$TMP/print.zip" --threads 2 &&
unzip -t "$TMP/print.zip" | sed 's/  */ /g' && unzip -p "$TMP/print.zip" ConfigFile.xml &&
unzip -p "$TMP/print.zip" layer_3.png | cmp - "$TMP/stack/layer-00003.png" && echo "zip layer 3 = stack layer 3"
