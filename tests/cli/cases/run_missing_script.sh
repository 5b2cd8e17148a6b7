$HOVOX run tests/lua/scripts/no_such_script.lua
