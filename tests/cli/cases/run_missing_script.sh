# a script that cannot be read: exit 4, in hovox's form 'SCRIPT: cannot open: reason' (Lua says
# 'cannot open SCRIPT: reason'); a directory the same way
$HOVOX run tests/lua/scripts/no_such_script.lua; echo "rc=$?"
$HOVOX run tests/lua/scripts; echo "rc=$?"
