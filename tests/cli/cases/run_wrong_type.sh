$HOVOX run tests/lua/scripts/wrong_type.lua
