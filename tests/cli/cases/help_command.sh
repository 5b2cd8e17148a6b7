# `hovox help COMMAND` is `hovox COMMAND --help` (exit 0, the same text); an unknown command, or
# two, exit 2
$HOVOX help layers >"$TMP/a"; echo "rc=$?"
$HOVOX layers --help >"$TMP/b"
cmp "$TMP/a" "$TMP/b" && echo "the same help"
$HOVOX --help tray | head -n 1
$HOVOX help nope; echo "rc=$?"
$HOVOX help layers tray; echo "rc=$?"
