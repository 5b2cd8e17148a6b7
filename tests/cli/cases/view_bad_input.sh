# hovox view refuses, with one message, an exit code and no page: a missing path, a directory that
# is not a stack, a damaged manifest, a missing layer, a layer unlike the manifest, a bad option
cd "$TMP"
"$HOVOX" generate box sx=10 sy=6 sz=2 -o b.stl >/dev/null
"$HOVOX" layers --mesh b.stl -o st --mode mask --dpi 50,50 --layer-height 1 -q >/dev/null
"$HOVOX" view nothing; echo "rc=$?"
mkdir empty
"$HOVOX" view empty; echo "rc=$?"
"$HOVOX" view st -o page.txt; echo "rc=$?"
"$HOVOX" view st --cuts 0; echo "rc=$?"
mv st/layer-00001.png away.png
"$HOVOX" view st; echo "rc=$?"
cp st/layer-00000.png st/layer-00001.png
"$HOVOX" generate box sx=1 sy=1 sz=1 -o s.stl >/dev/null
"$HOVOX" layers --mesh s.stl -o small --mode mask --dpi 50,50 --layer-height 1 -q >/dev/null
cp small/layer-00000.png st/layer-00001.png
"$HOVOX" view st; echo "rc=$?"
cp away.png st/layer-00001.png
head -c 200 st/manifest.json >m && mv m st/manifest.json
"$HOVOX" view st; echo "rc=$?"
printf '{"generator": "hovox", "mode": "mask", "width": 2, "height": 2, "bit_depth": 1, "dpi": [1, 1], "layer_height_mm": 1, "pixel_mm": [1, -1], "origin_mm": [0, 0], "materials": [], "layers": [{"index": 0, "file": "../../etc/passwd", "z_mm": 0}]}' >st/manifest.json
"$HOVOX" view st; echo "rc=$?"
ls st empty | grep -c html
"$HOVOX" view b.stl; echo "rc=$?"
ls | grep -c html
