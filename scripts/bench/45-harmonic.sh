# scripts/bench/45-harmonic.sh - issue 4: the harmonic field between two labelled regions
# (conjugate gradients with a multigrid preconditioner) on a 128^3 bar between its end faces
# and a ball between two caps; medians. No anchor: scipy has no Laplace solver on masks.
echo
echo "== harmonic: 128^3, tol 1e-6 (bar: exact solution linear)"
drv=$BUILD/bench-tools/bench_harmonic
if [ ! -x "$drv" ]; then
    echo "skipped: $drv not built (make bench-tools)"
else
    "$drv" 128 "$runs" 1e-6
fi
