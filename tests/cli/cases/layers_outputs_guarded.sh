# --background needs halftone; an existing --gcvf file is kept unless --force; fractions
# manifests give every layer a "file" (the first material's) and "files", z_mm tidy
$HOVOX generate box sx=4 sy=4 sz=4 -o "$TMP/b.stl" >/dev/null
$HOVOX layers --mesh "$TMP/b.stl" -o "$TMP/s1" --mode mask --dpi 50,50 --layer-height 0.3 --background '#ffffff' -q
echo "rc=$?"
echo "keep me" >"$TMP/old.zip"
$HOVOX layers --mesh "$TMP/b.stl" -o "$TMP/s2" --mode mask --dpi 50,50 --layer-height 0.3 --gcvf "$TMP/old.zip" -q >/dev/null
echo "rc=$?"; cat "$TMP/old.zip"; ls "$TMP"
$HOVOX voxelize "$TMP/b.stl" -o "$TMP/b.vdb" --dims 8 >/dev/null &&
$HOVOX grade "$TMP/b.vdb" -o "$TMP/g.vdb" --materials A,B --frf point:0,0,0 --ranges 0,4,0 --f d/dg --ms 1,0 --me 0,1 >/dev/null &&
$HOVOX layers "$TMP/g.vdb" --mesh "$TMP/b.stl" -o "$TMP/fr" --mode fractions --dpi 50,50 --layer-height 0.3 --layers 0:3 -q >/dev/null &&
grep -o '{"index.*}' "$TMP/fr/manifest.json"
