# Output paths that are FIFOs (or devices such as /dev/null) are written into, never replaced
# by the rename that puts a finished file in place; what the reader gets is the same file.
cd "$TMP" || exit 1
$HOVOX generate box sx=4 sy=4 sz=4 -o b.stl >/dev/null
$HOVOX voxelize b.stl -o b.vdb --dims 8 >/dev/null
$HOVOX grade b.vdb -o g.vdb --materials A,B --frf point:0,0,0 --ranges 0,4,0 --f d/dg --ms 1,0 --me 0,1 >/dev/null
$HOVOX export g.vdb -o ref.vti -q >/dev/null
$HOVOX render g.vdb -o ref.tif --size 16x16 -q >/dev/null
$HOVOX render g.vdb -o ref.png --size 16x16 -q >/dev/null
mkfifo out.vti out.tif out.png
for ext in vti tif png; do
    (timeout 60 cat out.$ext >got.$ext) &
    case $ext in
    vti) $HOVOX export g.vdb -o out.vti ;;
    *) $HOVOX render g.vdb -o out.$ext --size 16x16 ;;
    esac
    echo "$ext: exit $?"
    wait
    # TIFF carries a DateTime tag: compare its size, the others byte for byte
    if [ $ext = tif ]; then test "$(wc -c <ref.tif)" = "$(wc -c <got.tif)"; else cmp ref.$ext got.$ext; fi &&
        echo "$ext: reader got the file"
    test -p out.$ext && echo "$ext: still a FIFO"
done
echo "temporary files left: $(ls -a | grep -c tmp)"
