#!/bin/sh
# tests/samples/run.sh - every sample script runs as a test (into a fresh directory) and must
# leave its .vdb, CSV and PNG outputs (run with the arguments of its "-- test-args:" line); then the Lua API test scripts (tests/lua/test_*.lua).
set -u
: "${HOVOX:?set HOVOX to the hovox binary}"
SHARED=$(cd "${SHARED:-tests/data}" && pwd)
pass=0
fail=0
for s in samples/*.lua; do
    out=$(mktemp -d)
    # a sample may name smaller arguments for the test run: "-- test-args: 96 700:704"
    targs=$(sed -n 's/^-- test-args: //p' "$s")
    # shellcheck disable=SC2086
    if "$HOVOX" run "$s" "$out" $targs >"$out/.log" 2>&1 && ls "$out"/*.vdb >/dev/null 2>&1 &&
        ls "$out"/*.csv >/dev/null 2>&1 && ls "$out"/*.png >/dev/null 2>&1 && grep -q "^outputs in" "$out/.log"; then
        pass=$((pass + 1))
    else
        fail=$((fail + 1))
        echo "--- sample $s failed:"
        cat "$out/.log"
        ls "$out"
    fi
    rm -rf "$out"
done
for t in tests/lua/test_*.lua; do
    out=$(mktemp -d)
    if "$HOVOX" run "$t" "$out" "$SHARED" >"$out/.log" 2>&1; then
        pass=$((pass + 1))
    else
        fail=$((fail + 1))
        echo "--- $t failed:"
        cat "$out/.log"
    fi
    rm -rf "$out"
done
echo "samples and Lua tests: $pass passed, $fail failed"
[ $fail = 0 ]
