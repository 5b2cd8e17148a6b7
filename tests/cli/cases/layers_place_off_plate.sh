# `layers --place` off the plate is refused as `tray` refuses it (issue 32 item 15: 1000,100 and
# -50,-50 on the J750 were accepted); a box that touches the plate's edges is on it.
cd "$TMP"
"$HOVOX" generate box max=20,10,2 -o b.stl >/dev/null
for at in 1000,100 -50,-50 485,40 40,388; do
    "$HOVOX" layers --mesh b.stl --mode mask -o l --place $at --dry-run; echo "rc=$?"
done
"$HOVOX" tray -o t --part b.stl:VeroPureWhite@485,40 --dry-run; echo "rc=$?"
"$HOVOX" layers --mesh b.stl --mode mask -o l --place 10,5 --dry-run >/dev/null; echo "rc=$?"
"$HOVOX" layers --mesh b.stl --mode mask -o l --place 480,385 --dry-run >/dev/null; echo "rc=$?"
ls
