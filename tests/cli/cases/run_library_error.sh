$HOVOX run tests/lua/scripts/library_error.lua
