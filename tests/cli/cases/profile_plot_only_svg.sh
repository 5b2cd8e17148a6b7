$HOVOX profile tests/data/models/linear2.vdb --from 0,5,6 --to 9.5,5,6 --plot "$TMP/p.SVG" --size 600,400 --y-range auto -q &&
ls "$TMP" && grep -o "<svg[^>]*>" "$TMP/p.SVG" | grep -o "width=\"[0-9]*pt\" height=\"[0-9]*pt\""
