# scripts/bench/13-3mf-one-core.sh - issue 26's one figure: `hovox info` on the 1,000,000-facet knot
# as 3MF (written by lib3mf) against the binary STL reader on ONE core (taskset -c 0), CPU time
# (user + sys) of runs interleaved STL, 3MF, STL, ... so both see the same load; medians of
# BENCH_RUNS3MF rounds (default 11). Goal: 3MF <= 1.5x. The files are 12-mesh-formats.sh's.
echo
echo "== 3MF read on one core: info on the 1,000,000-facet knot, CPU time, taskset -c 0 (goal 3MF <= 1.5x binary STL)"
mesh=$work/knot1m.stl
[ -f "$mesh" ] || "$HOVOX" generate knot facets=1000000 -o "$mesh"
[ -f "$work/knot1m.3mf" ] || "$BUILD/bench-tools/bench_mesh_formats" "$mesh" "$work/knot1m"
# cpu CMD...  CPU seconds (user + sys) of one run of CMD on core 0, its output discarded
cpu() {
    /usr/bin/python3 -c 'import resource, subprocess, sys
r = subprocess.run(["taskset", "-c", "0"] + sys.argv[1:], stdout=subprocess.DEVNULL)
u = resource.getrusage(resource.RUSAGE_CHILDREN)
print("%.4f" % (u.ru_utime + u.ru_stime))
sys.exit(r.returncode)' "$@"
}
for ext in stl 3mf; do "$HOVOX" info "$work/knot1m.$ext" >/dev/null; done # warm the page cache
c_stl="" c_3mf=""
i=0
while [ $i -lt "${BENCH_RUNS3MF:-11}" ]; do
    c_stl="$c_stl $(cpu "$HOVOX" info "$mesh")"
    c_3mf="$c_3mf $(cpu "$HOVOX" info "$work/knot1m.3mf")"
    i=$((i + 1))
done
# shellcheck disable=SC2086
m_stl=$(median_of $c_stl)
# shellcheck disable=SC2086
m_3mf=$(median_of $c_3mf)
printf "%-12s %7.3f s CPU   (runs %s)\n" "binary STL" "$m_stl" "$(eval spread_of \$c_stl)"
printf "%-12s %7.3f s CPU   %sx STL   (runs %s)\n" "3mf" "$m_3mf" "$(ratio "$m_3mf" "$m_stl")" "$(eval spread_of \$c_3mf)"
