-- the known ways out of a Lua sandbox are closed under --sandbox: the debug library (the real
-- io.open is an upvalue of its wrapper), precompiled chunks (Lua does not verify bytecode), and
-- require of files (the file searcher accepts bytecode)
local out = arg[1]
print("debug:", debug)
print("bytecode:", select(2, load(string.dump(function() return 1 end))))
print("text chunks:", load("return 1 + 1")())
print("require a file:", (select(2, pcall(require, "hovox_no_such_module")):gsub("\n.*", "")))
print("require hovox:", require("hovox") == hovox)
local ok, err = pcall(io.open, "/tmp/hovox-sandbox-escape.txt", "w")
print("write outside:", ok, err)
local f = assert(io.open(out .. "/inside.txt", "w"))
f:write("ok\n")
f:close()
print("write inside: ok")
-- a symbolic link inside the output directory that leads out of it (made by the test)
local lok, lerr = pcall(io.open, out .. "/link", "w")
print("write through a link out:", lok, lerr)
local mok, merr = pcall(function() hovox.generate.sphere{segments = 8, rings = 4}:save(out .. "/link") end)
print("save through a link out:", mok, merr)
-- the C side of objects is reached through methods only
print("metatable:", getmetatable(hovox.generate.sphere{segments = 8, rings = 4}))
