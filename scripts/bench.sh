#!/bin/sh
# scripts/bench.sh - `make bench`: each figure an issue names, measured against its anchor on
# the same input in the same run (medians of several runs, via hyperfine), plus peak RSS.
# BENCH_ONLY=name runs one section; BENCH_RUNS=n sets the runs per command (default 5).
set -eu
: "${HOVOX:=build/hovox}"
: "${BUILD:=build}"
runs=${BENCH_RUNS:-5}
work=${BENCH_DIR:-$BUILD/bench}
mkdir -p "$work"
only=${BENCH_ONLY:-}

# median <name> <command...>: prints the median wall time in seconds of <runs> runs
median() {
    name=$1
    shift
    hyperfine -N --warmup 1 --runs "$runs" --export-json "$work/$name.json" "$*" >/dev/null 2>&1 ||
        hyperfine --warmup 1 --runs "$runs" --export-json "$work/$name.json" "$*" >/dev/null
    /usr/bin/python3 -c "import json,sys; print('%.4f' % json.load(open(sys.argv[1]))['results'][0]['median'])" "$work/$name.json"
}
# peak_rss <command...>: peak resident set size in MiB
peak_rss() {
    /usr/bin/time -f %M "$@" 2>&1 >/dev/null | tail -n 1 | awk '{printf "%.1f", $1 / 1024}'
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", a / b }'; }
want() { [ -z "$only" ] || [ "$only" = "$1" ]; }

echo "hovox bench on $(nproc) cores, $runs runs per command (medians)"

if want info; then
    echo
    echo "== info: 1,000,000-facet binary STL vs admesh (goal: <= 1.0x)"
    mesh=$work/knot1m.stl
    [ -f "$mesh" ] || "$HOVOX" generate knot facets=1000000 -o "$mesh"
    t_h=$(median info_hovox "$HOVOX" info "$mesh")
    t_a=$(median info_admesh admesh "$mesh")
    echo "hovox info  $t_h s   (peak $(peak_rss "$HOVOX" info "$mesh") MiB)"
    echo "admesh      $t_a s   (peak $(peak_rss admesh "$mesh") MiB)"
    echo "ratio       $(ratio "$t_h" "$t_a")x admesh"
    echo
    echo "== start-up: hovox --version (goal: <= 20 ms)"
    echo "hovox --version  $(median version "$HOVOX" --version) s"
fi
