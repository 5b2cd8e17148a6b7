local out = arg[1]
local function try(name, fn, ...)
  local ok, err = pcall(fn, ...)
  print(name, ok and "ACCEPTED" or ("refused: " .. tostring(err):gsub("\n", " ")))
end
