# issue 32.2: the time limit and Ctrl-C/SIGTERM end a script whatever it runs: pcall, xpcall and
# coroutines cannot catch the stop (raised again: the script's line); a backtracking pattern, a
# looping message handler, a looping finalizer (during the script and at its close) never return
# to a hook, so the watchdog ends them half a second later (exit 3, or 130 on a signal), leaving
# no temporary of a library job behind. (timeout -k: today these run until killed, rc=137.)
cd "$TMP" || exit 1
run() { timeout --preserve-status -k 5 "$@"; echo "rc=$?"; }
printf 'while true do pcall(function() while true do end end) end\n' >pcall.lua
printf 'while true do xpcall(function() while true do end end, function(m) return m end) end\n' >xpcall.lua
printf 'while true do coroutine.resume(coroutine.create(function() while true do end end)) end\n' >coroutine.lua
printf 'local s = string.rep("a", 40)\nprint(string.find(s, string.rep("a*", 30) .. "b"))\n' >pattern.lua
printf 'xpcall(error, function() while true do end end)\n' >handler.lua
printf 'setmetatable({}, {__gc = function() while true do end end})\ncollectgarbage()\n' >finalizer.lua
printf 'X = setmetatable({}, {__gc = function() while true do end end})\nprint("script done")\n' >close.lua
for s in pcall xpcall coroutine pattern handler finalizer close; do run 20 $HOVOX run --max-time 0.5 $s.lua; done
# signals, whatever runs: exit 130 within a second of the signal (sent after 1 s; 1.5 s allowed
# for a loaded machine)
signal() {
    t0=$(date +%s%N)
    run -s "$1" 1 $HOVOX run "$2"
    [ $(($(date +%s%N) - t0)) -lt 2500000000 ] && echo "ended in time"
}
for s in pcall pattern finalizer close; do signal INT $s.lua; done
signal TERM handler.lua
# a library job stuck in a finalizer: ended, its temporaries removed
mkdir out
cat >job.lua <<'LUA'
local box = hovox.generate.box{min = {0, 0, 0}, max = {10, 10, 10}}
collectgarbage("incremental", 0, 100, 0)
local armed = false
for _ = 1, 50 do setmetatable({}, {__gc = function() if armed then while true do end end end}) end
armed = true
hovox.contours(box, {layer_height = 0.01, per_layer = "out/many", output = "out/many.cli"})
LUA
run 20 $HOVOX run --max-time 1 job.lua
ls -A out
