# scripts/bench/96-mpi.sh - issue 15: strong scaling of the gear stack (Wu's gear of make demo,
# 128 voxels, 3 materials, J750 halftone, 1,461 layers of 1864 x 934) from 1 to 2 MPI ranks on
# this 2-core machine, one thread per rank; against the threaded single process.
# Goal: parallel efficiency T(1 rank) / (2 T(2 ranks)) >= 0.85.
[ -x "$BUILD/hovox-mpi" ] || { echo; echo "== mpi: skipped (no hovox-mpi: install Open MPI)"; return 0 2>/dev/null || exit 0; }
echo
echo "== mpi: gear stack (1,461 layers), 1 -> 2 ranks, one thread each, vs 2 threads in one process (goal: efficiency >= 0.85)"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
mw="$work/mpi"
mkdir -p "$mw"
if [ ! -f "$mw/gear.vdb" ]; then
    "$HOVOX" generate gear -o "$mw/gear.stl" >/dev/null
    "$HOVOX" voxelize "$mw/gear.stl" --dims 128 -o "$mw/occ.vdb" -q >/dev/null
    "$HOVOX" grade "$mw/occ.vdb" -o "$mw/gear.vdb" --materials A,B,C --frf axis:0,0,0:0,0,1 \
        --ranges 9.54,9.54,20.37 --ms 0,0.9,0.1 --me 0.9,0,0.1 -q
fi
L="$mw/gear.vdb --mesh $mw/gear.stl -o $mw/stack --force -q"
saved_runs=$runs
runs=$((runs < 3 ? runs : 3))
t1=$(median mpi_1 "$HOVOX" layers $L --threads 1)
t1m=$(median mpi_1r mpirun -np 1 "$BUILD/hovox-mpi" layers $L --threads 1)
t2=$(median mpi_2r mpirun -np 2 "$BUILD/hovox-mpi" layers $L --threads 1)
tt=$(median mpi_2t "$HOVOX" layers $L --threads 2)
runs=$saved_runs
echo "  hovox, 1 thread                $t1 s"
echo "  hovox-mpi, 1 rank              $t1m s"
echo "  hovox-mpi, 2 ranks             $t2 s   efficiency $(awk -v a="$t1" -v b="$t2" 'BEGIN { printf "%.2f", a / (2 * b) }')"
echo "  hovox, 2 threads               $tt s   efficiency $(awk -v a="$t1" -v b="$tt" 'BEGIN { printf "%.2f", a / (2 * b) }')"
