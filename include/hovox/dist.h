/* hovox/dist.h - one stack job across processes (MPI ranks) without hovox linking MPI: the
 * caller supplies three collective operations (hovox-mpi implements them with MPI_Bcast,
 * MPI_Reduce and MPI_Allreduce). Every process plans the same job; the layers are split into
 * contiguous ranges aligned to the halftoning restart blocks (HV_HALFTONE_BLOCK layers) and
 * balanced by estimated cost (object pixels per layer from the contours' areas, plus the empty
 * pixels); each process writes its own layers into the temporary directory rank 0 made, rank 0
 * gathers the statistics, writes the manifest (and the GCVF zip) and renames the directory. The
 * files are byte-identical to a single-process run. When any process fails, every process
 * stops, rank 0 removes the temporary directory, and every process returns the failing
 * status; only the process that failed holds the message (the others hold "another process
 * failed"), so a front end prints it once.
 *
 * Collectives are called by every process, in the same order, from the thread that called
 * the hovox function. */
#ifndef HOVOX_DIST_H
#define HOVOX_DIST_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hv_dist {
    int rank, size;
    void *ctx;
    /* Copy `bytes` bytes at buf from process `root` to every process. */
    void (*bcast)(void *ctx, void *buf, size_t bytes, int root);
    /* Element-wise sum of every process's n values into process 0's (others' unchanged). */
    void (*sum_to_root)(void *ctx, double *values, size_t n);
    /* The largest of every process's `value`, returned on every process. */
    int (*max_all)(void *ctx, int value);
} hv_dist;

#ifdef __cplusplus
}
#endif
#endif
