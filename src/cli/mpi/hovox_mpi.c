/* src/cli/mpi/hovox_mpi.c - `mpirun -np N hovox-mpi layers|tray ...`: the stack commands of hovox
 * across MPI ranks (hovox/dist.h), with the same options. Built only when Open MPI is installed
 * (Makefile: mpicc); the plain hovox never links MPI. Rank 0 prints the plan and the summary;
 * an error is printed by the rank that had it. Works under mpirun and under Slurm's srun (MPI
 * picks the ranks up from either). */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "hovox/core.h"
#include "hovox/dist.h"

typedef struct mpi_ctx {
    int failed_elsewhere; /* a failure agreed on, which another rank had */
    int agreed;           /* the ranks agreed on a failure (all of them stop cleanly) */
    int fail_armed;       /* test hook: fail once the job is under way */
    int fail_now;
} mpi_ctx;

static mpi_ctx g_ctx;

static void bcast(void *ctx, void *buf, size_t bytes, int root)
{
    (void)ctx;
    MPI_Bcast(buf, (int)bytes, MPI_BYTE, root, MPI_COMM_WORLD);
}

static void sum_to_root(void *ctx, double *v, size_t n)
{
    (void)ctx;
    int rank;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    for (size_t done = 0; done < n;) { /* MPI counts are ints */
        int k = (int)(n - done > (1u << 30) ? (1u << 30) : n - done);
        MPI_Reduce(rank == 0 ? MPI_IN_PLACE : v + done, v + done, k, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
        done += (size_t)k;
    }
}

static int max_all(void *ctx, int value)
{
    mpi_ctx *c = ctx;
    int out = value;
    MPI_Allreduce(&value, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (out != 0 && value == 0) c->failed_elsewhere = 1;
    if (out != 0) c->agreed = 1;
    if (c->fail_armed) c->fail_now = 1; /* the plan is agreed: the layers are being written */
    return out;
}

static int g_rank;

/* Print here? Not when another rank had the failure, nor for Ctrl-C (mpirun forwards it to every
 * rank) except on rank 0: one message, as in a plain run. */
static int failed_here(void) { return !g_ctx.failed_elsewhere && !(g_rank != 0 && cli_interrupted()); }

/* The test hook's failure: this rank stops with an error while the layers are written, as a
 * process that cannot write would (the others must stop too and leave nothing). */
static int fail_soon(void *user)
{
    mpi_ctx *c = user;
    return c->fail_now;
}

int main(int argc, char **argv)
{
    int provided, rank, size;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    g_rank = rank;
    hv_dist d = {rank, size, &g_ctx, bcast, sum_to_root, max_all};
    const cli_spec *spec = NULL;
    if (argc >= 2 && strcmp(argv[1], "layers") == 0) spec = &cmd_layers;
    if (argc >= 2 && strcmp(argv[1], "tray") == 0) spec = &cmd_tray;
    int rc;
    if (!spec) {
        if (rank == 0)
            fprintf(stderr, "usage: mpirun -np N hovox-mpi layers|tray [options] (the options of hovox layers or "
                            "hovox tray)\n");
        rc = EXIT_USAGE;
    } else {
        if (rank != 0 && !freopen("/dev/null", "w", stdout)) return EXIT_IO; /* rank 0 reports */
        cli_dist = &d;
        cli_failed_here = failed_here;
        cli_install_signals();
        /* a test hook: HOVOX_MPI_FAIL_RANK=r makes rank r stop with an error partway */
        const char *fail = getenv("HOVOX_MPI_FAIL_RANK");
        if (fail && atoi(fail) == rank) {
            g_ctx.fail_armed = 1;
            hv_set_cancel_check(fail_soon, &g_ctx);
        }
        rc = cli_main(spec, argc - 1, argv + 1);
        /* a failure this rank had before the ranks could agree on it (a file it alone cannot
         * read, a check before the job): the others may be waiting in a collective, so the job
         * is aborted; rank 0's temporary directory is removed by the next run to the same place */
        if (rc != EXIT_OK && !g_ctx.agreed && size > 1) {
            fflush(stderr);
            MPI_Abort(MPI_COMM_WORLD, rc);
        }
    }
    MPI_Finalize();
    return rc;
}
