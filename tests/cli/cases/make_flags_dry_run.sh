# smsg item 6: the Makefile's flag tracking. A build keeps the WERROR it was made with (so `make demo`
# or `make bench` after `make WERROR=1` compiles nothing again); WERROR=0 given rebuilds; `make -n`
# shows only what would be compiled and writes nothing (the flags are compared when the Makefile is
# read, not by a recipe that -n cannot run).
m() { env -u MAKEFLAGS -u MAKELEVEL -u MFLAGS make --no-print-directory BUILD="$TMP/b" "$@" 2>&1; }
o="$TMP/b/obj/src/core/error.o"
echo "WERROR=1: $(m "$o" WERROR=1 | grep -c -- '-Werror .*-c src/core/error.c') compiled with -Werror"
echo "the flags say -Werror: $(grep -c -- ' -Werror ' "$TMP/b/.flags")"
echo "again, WERROR not given: $(m "$o" | grep -c -- ' -c src/core/error.c') compiled"
echo "dry run, WERROR=0: $(m -n "$o" WERROR=0 | grep -c -- ' -c src/core/error.c') to compile"
echo "after the dry run the flags still say -Werror: $(grep -c -- ' -Werror ' "$TMP/b/.flags")"
echo "dry run with nothing changed: $(m -n "$o" | grep -c -- ' -c src/core/error.c') to compile"
echo "WERROR=0: $(m "$o" WERROR=0 | grep -c -- ' -c src/core/error.c') compiled"
echo "the flags say -Werror: $(grep -c -- ' -Werror ' "$TMP/b/.flags")"
