# volume mode with clips, a clip box, an explicit orthographic camera, a transparent background
$HOVOX generate box sx=20 sy=20 sz=10 -o "$TMP/b.stl" >/dev/null && $HOVOX voxelize "$TMP/b.stl" --dims 20 -o "$TMP/b.vdb" -q >/dev/null &&
$HOVOX render "$TMP/b.vdb" --clip 'x>0&y<0' --clip 'z > 8' --clip-box 1,1,1,-1,-1,-1 --eye 40,-30,25 --target 0,0,0 \
    --up 0,0,1 --ortho --background transparent --density 0.5 --step 0.5 --aa 2 --flat --threads 2 \
    --size 40x30 -o "$TMP/b.png" && od -An -tu1 -j16 -N10 "$TMP/b.png"; ls "$TMP"
