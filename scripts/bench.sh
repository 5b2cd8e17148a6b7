#!/bin/sh
# scripts/bench.sh - `make bench`: each figure an issue names, measured against its anchor on
# the same input in the same run (medians of several runs, via hyperfine), plus peak RSS.
# Sections are scripts/bench/NN-name.sh, sourced in order.
#   BENCH_ONLY=name   run only sections whose file name contains `name`
#   BENCH_RUNS=n      runs per command (default 5)
set -eu
: "${HOVOX:=build/hovox}"
: "${BUILD:=build}"
runs=${BENCH_RUNS:-5}
work=${BENCH_DIR:-$BUILD/bench}
mkdir -p "$work"
here=$(dirname "$0")
. "$here/bench/lib.sh"
echo "hovox bench on $(nproc) cores, $runs runs per command (medians)"
for section in "$here"/bench/[0-9]*.sh; do
    case "$section" in *"${BENCH_ONLY:-}"*) . "$section" ;; esac
done
