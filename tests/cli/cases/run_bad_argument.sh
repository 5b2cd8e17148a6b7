$HOVOX run tests/lua/scripts/bad_argument.lua
