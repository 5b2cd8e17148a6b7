#!/bin/sh
# tests/cli/run.sh - CLI tests that pin stdout, stderr and the exit code.
# Each cases/NAME.sh runs from the repository root with $HOVOX (the binary), $SHARED (the
# shared material) and $TMP (a fresh directory). Expected output lives next to it in
# NAME.out, NAME.err and NAME.rc; the path of $SHARED and $TMP print as "$SHARED", "$TMP".
# UPDATE=1 rewrites the expected files from the current behaviour (review the diff!);
# ONLY=pattern restricts the run (and the update) to cases whose name contains it.
set -u
: "${HOVOX:?set HOVOX to the hovox binary}"
SHARED=$(cd "${SHARED:-tests/data}" && pwd)
export HOVOX SHARED
here=$(dirname "$0")
pass=0
fail=0
for case in "$here"/cases/*.sh; do
    name=${case%.sh}
    case "$(basename "$name")" in *"${ONLY:-}"*) ;; *) continue ;; esac
    TMP=$(mktemp -d)
    export TMP
    sh "$case" >"$TMP/.stdout" 2>"$TMP/.stderr"
    rc=$?
    for f in stdout stderr; do
        sed -e "s|$SHARED|\$SHARED|g" -e "s|$TMP|\$TMP|g" "$TMP/.$f" >"$TMP/.$f.n"
    done
    if [ "${UPDATE:-0}" = 1 ]; then
        cp "$TMP/.stdout.n" "$name.out"
        cp "$TMP/.stderr.n" "$name.err"
        echo "$rc" >"$name.rc"
    fi
    ok=1
    if ! cmp -s "$TMP/.stdout.n" "$name.out"; then
        ok=0
        echo "--- $(basename "$name"): stdout differs"
        diff "$name.out" "$TMP/.stdout.n" | head -20
    fi
    if ! cmp -s "$TMP/.stderr.n" "$name.err"; then
        ok=0
        echo "--- $(basename "$name"): stderr differs"
        diff "$name.err" "$TMP/.stderr.n" | head -20
    fi
    if [ "$rc" != "$(cat "$name.rc")" ]; then
        ok=0
        echo "--- $(basename "$name"): exit code $rc, expected $(cat "$name.rc")"
    fi
    rm -rf "$TMP"
    if [ $ok = 1 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); fi
done
echo "cli: $pass passed, $fail failed"
[ $fail = 0 ]
