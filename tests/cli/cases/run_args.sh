$HOVOX run tests/lua/scripts/args.lua one two
