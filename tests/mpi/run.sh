#!/bin/sh
# tests/mpi/run.sh - hovox-mpi against the plain command (issue 15): mpirun with 1, 2 and 4
# ranks on a small graded model (blue noise; error diffusion with a GCVF zip) and on a small
# tray, every file compared byte for byte; then a rank that fails on purpose: the error is
# printed once, the exit code is nonzero, and nothing is left behind.
# Usage: HOVOX=build/hovox HOVOX_MPI=build/hovox-mpi sh tests/mpi/run.sh
set -u
: "${HOVOX:?}" "${HOVOX_MPI:?}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail=0
check() { # name: diff the two outputs
    if diff -r "$T/$1" "$T/$2" >/dev/null && { [ -z "${3:-}" ] || cmp -s "$T/$3" "$T/$4"; }; then
        echo "mpi: $5 identical"
    else
        echo "mpi: $5 DIFFERS"
        fail=1
    fi
}
"$HOVOX" generate gear height=4 -o "$T/g.stl" >/dev/null
"$HOVOX" voxelize "$T/g.stl" --voxel-size 0.6 -o "$T/o.vdb" -q >/dev/null
"$HOVOX" grade "$T/o.vdb" -o "$T/g.vdb" --materials A,B,C --frf axis:0,0,0:0,0,1 --ranges 9.54,9.54,20.37 \
    --ms 0,0.9,0.1 --me 0.9,0,0.1 -q
L="$T/g.vdb --mesh $T/g.stl --dpi 300,150 --layer-height 0.05"
"$HOVOX" layers $L -o "$T/one" -q >/dev/null
"$HOVOX" layers $L -o "$T/one_ed" --halftone error --gcvf "$T/one_ed.zip" -q >/dev/null
R="--part $T/g.vdb,$T/g.stl@60,60 --part $T/g.vdb,$T/g.stl@150,60,90 --part $T/g.stl:VeroPureWhite@100,200 \
   --resin A=VeroCyan-V --resin B=VeroMagenta-V --resin C=VeroYellow-V --layers 0:90"
"$HOVOX" tray $R -o "$T/tray_one" --gcvf "$T/tray_one.zip" -q >/dev/null
for n in 1 2 4; do
    mpirun -np $n "$HOVOX_MPI" layers $L -o "$T/l$n" --threads 1 -q >/dev/null
    check one "l$n" "" "" "layers, $n rank(s)"
    mpirun -np $n "$HOVOX_MPI" layers $L -o "$T/e$n" --halftone error --gcvf "$T/e$n.zip" --threads 1 -q >/dev/null
    check one_ed "e$n" one_ed.zip "e$n.zip" "layers --halftone error --gcvf, $n rank(s)"
    mpirun -np $n "$HOVOX_MPI" tray $R -o "$T/t$n" --gcvf "$T/t$n.zip" --threads 1 -q >/dev/null
    check tray_one "t$n" tray_one.zip "t$n.zip" "tray --gcvf, $n rank(s)"
done
# rank 1 of 2 fails while the layers are written
HOVOX_MPI_FAIL_RANK=1 mpirun -np 2 "$HOVOX_MPI" layers $L -o "$T/failed" --gcvf "$T/failed.zip" --threads 1 -q \
    >/dev/null 2>"$T/err"
rc=$?
n=$(grep -c '^hovox:' "$T/err")
left=$(ls -A "$T" | grep -c failed)
if [ $rc -ne 0 ] && [ "$n" = 1 ] && [ "$left" = 0 ]; then
    echo "mpi: a failing rank stops the job, one message, nothing left"
else
    echo "mpi: failing rank: exit $rc, $n messages, $left leftovers"
    cat "$T/err"
    fail=1
fi
# a rerun to the same place works
mpirun -np 2 "$HOVOX_MPI" layers $L -o "$T/failed" --threads 1 -q >/dev/null && check one failed "" "" "rerun after the failure"
# ranks given different jobs (issue 32 item 9): one message, exit 1, nothing written, for layers
# (another layer height on rank 1) and tray (another part on rank 1)
disagree() { # name, then the command of rank 0 and of rank 1 separated by ':'
    what=$1
    shift
    mpirun "$@" >/dev/null 2>"$T/err"
    rc=$?
    n=$(grep -c '^hovox:' "$T/err")
    left=$(ls -A "$T" | grep -c dis)
    if [ $rc = 1 ] && [ "$n" = 1 ] && [ "$left" = 0 ] && grep -q "planned a different job from rank 0's" "$T/err"; then
        echo "mpi: $what: one message, exit 1, nothing left"
    else
        echo "mpi: $what: exit $rc, $n messages, $left leftovers"
        cat "$T/err"
        fail=1
    fi
}
L2="$T/g.vdb --mesh $T/g.stl --dpi 300,150 --layer-height 0.06"
disagree "ranks with different layer heights" -np 1 "$HOVOX_MPI" layers $L -o "$T/dis" --threads 1 -q : \
    -np 1 "$HOVOX_MPI" layers $L2 -o "$T/dis" --threads 1 -q
disagree "ranks with different trays" -np 1 "$HOVOX_MPI" tray $R -o "$T/dis" --threads 1 -q : \
    -np 1 "$HOVOX_MPI" tray $R --part "$T/g.stl:VeroPureWhite@300,300" -o "$T/dis" --threads 1 -q
# threads beyond the cores a rank is bound to (issue 32 item 22): a warning on every rank that
# has them; none when each rank may use every core
mpirun -np 2 --bind-to core "$HOVOX_MPI" layers $L -o "$T/bound" --threads 2 -q >/dev/null 2>"$T/err"
n=$(grep -o 'warning: 2 threads on 1 processor' "$T/err" | wc -l)
mpirun -np 2 --bind-to none "$HOVOX_MPI" layers $L -o "$T/unbound" --threads 2 -q >/dev/null 2>"$T/err2"
m=$(grep -c 'warning' "$T/err2")
if [ "$n" = 2 ] && [ "$m" = 0 ]; then
    echo "mpi: --threads beyond a rank's binding warns on each rank; --bind-to none does not"
else
    echo "mpi: binding warnings: $n bound (expected 2), $m unbound (expected 0)"
    cat "$T/err" "$T/err2"
    fail=1
fi
exit $fail
