# scripts/bench/lib.sh - helpers for the bench sections (sourced by scripts/bench.sh).
# median NAME CMD...  median wall time (s) of $runs runs, via hyperfine (JSON kept in $work)
median() {
    name=$1
    shift
    hyperfine -N --warmup 1 --runs "$runs" --export-json "$work/$name.json" "$*" >/dev/null 2>&1 ||
        hyperfine --warmup 1 --runs "$runs" --export-json "$work/$name.json" "$*" >/dev/null
    /usr/bin/python3 -c "import json,sys; print('%.4f' % json.load(open(sys.argv[1]))['results'][0]['median'])" "$work/$name.json"
}
# peak_rss CMD...  peak resident set size in MiB of one run
peak_rss() {
    /usr/bin/time -f %M "$@" 2>&1 >/dev/null | tail -n 1 | awk '{printf "%.1f", $1 / 1024}'
}
# ratio A B  A/B with 3 decimals
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", a / b }'; }
