# issue 32.1: finalizers run by a binding's own allocations free its objects (self and arguments,
# of every class, through __close) while it runs: mesh:bodies, model:transform, model:grids and
# obj:regions crashed (SIGSEGV); every binding must finish on objects kept alive, or say "object
# was freed" (under make sanitize, any use after free is reported)
mkdir -p "$TMP/out"
$HOVOX run --sandbox --output-dir "$TMP/out" tests/lua/scripts/hostile_finalizer_frees.lua "$TMP/out"; echo "rc=$?"
