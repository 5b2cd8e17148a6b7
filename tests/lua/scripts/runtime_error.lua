local m = hovox.generate.box{}

error("boom")
