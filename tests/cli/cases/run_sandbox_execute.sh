$HOVOX run --sandbox tests/lua/scripts/sandbox_execute.lua
