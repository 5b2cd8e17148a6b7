# --layers splits give the same files as one run (error diffusion restarts every 32 layers;
# a range starting inside a block recomputes from the block start)
$HOVOX generate box sx=6 sy=4 sz=20 -o "$TMP/b.stl" &&
$HOVOX voxelize "$TMP/b.stl" --voxel-size 0.5 -o "$TMP/b.vdb" &&
$HOVOX grade "$TMP/b.vdb" -o "$TMP/g.vdb" --materials A,B,C --frf plane:0,0,0:0,0,1 --ranges 0,20,0 \
    --ms 0.6,0.3,0.1 --me 0.1,0.3,0.6 -q &&
for h in error bluenoise; do
    XDG_CACHE_HOME="$TMP/cache" $HOVOX layers "$TMP/g.vdb" --mesh "$TMP/b.stl" -o "$TMP/all-$h" --dpi 100,100 \
        --layer-height 0.2 --halftone $h --seed 3 -q >/dev/null &&
    XDG_CACHE_HOME="$TMP/cache" $HOVOX layers "$TMP/g.vdb" --mesh "$TMP/b.stl" -o "$TMP/a-$h" --dpi 100,100 \
        --layer-height 0.2 --halftone $h --seed 3 --layers :45 --threads 1 -q >/dev/null &&
    XDG_CACHE_HOME="$TMP/cache" $HOVOX layers "$TMP/g.vdb" --mesh "$TMP/b.stl" -o "$TMP/b-$h" --dpi 100,100 \
        --layer-height 0.2 --halftone $h --seed 3 --layers 45: -q >/dev/null &&
    echo "$h: $(ls "$TMP/all-$h" | grep -c png) layers, $(ls "$TMP/a-$h" | grep -c png) + $(ls "$TMP/b-$h" | grep -c png)" &&
    for f in "$TMP/all-$h"/layer-*.png; do
        n=$(basename "$f"); if [ -f "$TMP/a-$h/$n" ]; then cmp "$f" "$TMP/a-$h/$n"; else cmp "$f" "$TMP/b-$h/$n"; fi
    done && echo "$h: identical"
done
ls "$TMP/cache/hovox"
