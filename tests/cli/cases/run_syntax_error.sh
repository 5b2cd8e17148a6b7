$HOVOX run tests/lua/scripts/syntax_error.lua
