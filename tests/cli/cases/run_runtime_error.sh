$HOVOX run tests/lua/scripts/runtime_error.lua
