# The dry run's time estimate covers the layers asked for (--layers A:B), not the whole tray: a
# 200 x 150 x 100 mm box and a 100 x 100 x 5 mm plate (the plate's 186 layers are all below layer
# 1850): the whole tray, its first tenth (both parts), a tenth in the middle (the box alone: its
# share of the voxels, not the plate's) and the last 4 layers (under a second). The PNG estimate
# already followed the window.
cd "$TMP" || exit 1
"$HOVOX" generate box max=200,150,100 -o box.stl >/dev/null
"$HOVOX" generate box max=100,100,5 -o plate.stl >/dev/null
for w in 0:0 0:370 1850:2220 3700:3704; do
    [ $w = 0:0 ] && layers= || layers="--layers $w"
    # shellcheck disable=SC2086
    "$HOVOX" tray -o x --part box.stl:VeroPureWhite@120,100 --part plate.stl:VeroPureWhite@340,100 --dry-run $layers |
        grep -E '^(layers|estimate)'
done
ls x 2>&1 | sed 's/.*: //'
