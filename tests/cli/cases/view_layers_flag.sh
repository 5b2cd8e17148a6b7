# layers --view writes the page with the stack (before the stack is renamed into place), titled
# with the stack's name; --force replaces such a stack
cd "$TMP"
"$HOVOX" generate box sx=10 sy=6 sz=2 -o b.stl >/dev/null
"$HOVOX" layers --mesh b.stl -o st --mode mask --dpi 50,50 --layer-height 1 --view >"$TMP/.o"
echo "rc=$?"
sed 's/([0-9.]* [KM]iB)/(SIZE)/' "$TMP/.o"
ls st
grep -o '<title>[^<]*</title>' st/index.html
grep -c 'tmp-' st/index.html
"$HOVOX" layers --mesh b.stl -o st --mode mask --dpi 50,50 --layer-height 1 --force -q >/dev/null
echo "rc=$?"
ls st
"$HOVOX" layers --mesh b.stl -o st2 --mode mask --dpi 50,50 --layer-height 1 --view --dry-run
echo "rc=$?"
ls | grep -c st2
