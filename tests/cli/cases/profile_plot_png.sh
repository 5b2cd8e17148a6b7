$HOVOX profile tests/data/models/gap3.vdb --from -3,3.5,3.5 --to 27,3.5,3.5 -o "$TMP/p.csv" --plot "$TMP/p.png" --mark 12.5="gap starts" --title "gap3 along x" &&
ls "$TMP" && wc -l < "$TMP/p.csv" &&
# PNG signature, then the IHDR width and height
od -An -c -j1 -N3 "$TMP/p.png" && set -- $(od -An -tu1 -j16 -N8 "$TMP/p.png") && echo "$(($3 * 256 + $4)) x $(($7 * 256 + $8))"
