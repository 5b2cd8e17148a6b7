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
# wall CMD...  wall time (s) of one run of CMD, its output discarded (for interleaving runs of
# two commands by hand, so both see the same machine load)
wall() {
    /usr/bin/python3 -c 'import subprocess, sys, time
t = time.perf_counter()
r = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL)
print("%.4f" % (time.perf_counter() - t))
sys.exit(r.returncode)' "$@"
}
# wall_cpu CMD...  "WALL CPU" of one run of CMD: wall time and CPU time (user + sys of it and its
# children, s), its output discarded; CPU is the steadier figure on a loaded machine
wall_cpu() {
    /usr/bin/python3 -c 'import resource, subprocess, sys, time
t = time.perf_counter()
r = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL)
u = resource.getrusage(resource.RUSAGE_CHILDREN)
print("%.4f %.4f" % (time.perf_counter() - t, u.ru_utime + u.ru_stime))
sys.exit(r.returncode)' "$@"
}
# median_of X...  median of the numbers given; spread_of X...  "min-max"
median_of() { printf '%s\n' "$@" | sort -g | awk '{a[NR] = $1} END {printf "%.4f", NR % 2 ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
spread_of() { printf '%s\n' "$@" | sort -g | awk 'NR == 1 {lo = $1} {hi = $1} END {printf "%.3f-%.3f", lo, hi}'; }
# bench_tray_parts DIR  the bench tray's parts in DIR, made once: Wu's gear, shaft and a torus knot,
# voxelized and graded (gear.vdb, shaft.vdb, knot.vdb with their STLs) and a 1 mm pin (sections tray, colour)
bench_tray_parts() {
    tw=$1
    mkdir -p "$tw"
    if [ ! -f "$tw/knot.vdb" ]; then
        "$HOVOX" generate gear -o "$tw/gear.stl" >/dev/null
        "$HOVOX" voxelize "$tw/gear.stl" --dims 128 -o "$tw/gear_occ.vdb" -q >/dev/null
        "$HOVOX" grade "$tw/gear_occ.vdb" -o "$tw/gear.vdb" --materials A,B,C --frf axis:0,0,0:0,0,1 \
            --ranges 9.54,9.54,20.37 --ms 0,0.9,0.1 --me 0.9,0,0.1 -q
        "$HOVOX" generate cylinder -o "$tw/shaft.stl" >/dev/null
        "$HOVOX" voxelize "$tw/shaft.stl" --dims 256,97,97 -o "$tw/shaft_occ.vdb" -q >/dev/null
        "$HOVOX" grade "$tw/shaft_occ.vdb" -o "$tw/shaft.vdb" --materials A,B,C --frf contour --ranges 0,20.416,0 \
            --f 'sin(0.1538*d)' --ms 0,0,1 --me 0,0.2,0.8 -q
        "$HOVOX" generate knot -o "$tw/knot.stl" >/dev/null
        "$HOVOX" voxelize "$tw/knot.stl" --dims 160 -o "$tw/knot_occ.vdb" -q >/dev/null
        "$HOVOX" grade "$tw/knot_occ.vdb" -o "$tw/knot.vdb" --materials A,B,C --frf contour --ranges 0,4,0 \
            --ms 1,0,0 --me 0,0.5,0.5 -q
        "$HOVOX" generate box max=1,1,55 -o "$tw/pin.stl" >/dev/null
    fi
}
