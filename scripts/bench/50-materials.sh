# scripts/bench/50-materials.sh - issue 4: material evaluation throughput with a tabulated f
# (goal: >= 300 M voxel-evaluations/s on 2 cores): the kernel alone (re-evaluating into the
# grids) and end to end (allocating the material grids too).
echo
echo "== materials: evaluation throughput, one AGS on an axis, tabulated f (goal: >= 300 M/s)"
"$BUILD/bench-tools/bench_eval" 384 "$runs" 1
"$BUILD/bench-tools/bench_eval" 256 "$runs" 2
