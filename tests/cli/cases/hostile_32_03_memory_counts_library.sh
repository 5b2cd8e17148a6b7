# issue 32.3: --max-memory counts what the library holds for the script (models, meshes), not
# only the Lua heap: an operation whose plan exceeds what is left is refused at the script's line
# (exit 3 when not caught), a script that goes on allocating is stopped (exit 3), and the peak
# resident size stays near the limit (today: 1.8 GB and more under a 150M limit)
cd "$TMP" || exit 1
cat >models.lua <<'LUA'
local m = hovox.voxelize(hovox.generate.box{}, {dims = 160})
local o = hovox.object(m, hovox.materials{"A", "B"})
local keep = {}
for i = 1, 20 do keep[i] = o:evaluate() end -- 51 MiB each
print("held", #keep)
LUA
cat >caught.lua <<'LUA'
local m = hovox.voxelize(hovox.generate.box{}, {dims = 160})
local o = hovox.object(m, hovox.materials{"A", "B"})
local keep, refused = {}, 0
for i = 1, 20 do
  local ok, v = pcall(o.evaluate, o)
  if ok then keep[#keep + 1] = v else refused = refused + 1 end
end
print("some held", #keep > 0, "some refused", refused > 0)
LUA
cat >meshes.lua <<'LUA'
local keep = {}
for i = 1, 200 do keep[i] = hovox.generate.knot{facets = 200000} end -- 5 MiB each
print("held", #keep)
LUA
# the bound on the peak: 270 MiB; 1.2 GiB under AddressSanitizer (its shadow memory and its
# quarantine of freed blocks are resident too; the script's count is its allocator's)
bound=276480
ldd "$HOVOX" | grep -q libasan && bound=1258291
for s in models caught meshes; do
    /usr/bin/time -f %M -o peak.txt $HOVOX run --max-memory 150M $s.lua 2>err.txt; echo "rc=$?"
    sed 's/the limit of [0-9.]* MiB/the limit of (what is left) MiB/' err.txt >&2
    peak=$(tail -1 peak.txt)
    [ "$peak" -lt $bound ] && echo "peak resident size within its bound" || echo "peak resident size $peak KiB"
done
