# a slice stack (a directory holding manifest.json) where a scanned volume goes is told what it is
# and what shows it, not "st/layer-00000.png: not a DICOM file" (exit 1)
cd "$TMP"
"$HOVOX" generate box max=4,4,2 -o b.stl >/dev/null
"$HOVOX" layers --mesh b.stl -o st --mode mask --dpi 50,50 --layer-height 1 -q
"$HOVOX" info st; echo "rc=$?"
"$HOVOX" voxelize st --iso 0 -o v.vdb; echo "rc=$?"
