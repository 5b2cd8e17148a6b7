/* src/voxel/bitgrid.h - dense bit grids used while voxelizing: rows of 64-bit words along z,
 * one row per (i, j). The grid's (0,0,0) sits at volume index `lo` (multiples of 8), so
 * 8x8x8 blocks of the grid are the volume's leaves. */
#ifndef HOVOX_BITGRID_H
#define HOVOX_BITGRID_H

#include <stdint.h>

#include "hovox/core.h"

typedef struct hv_bitgrid {
    int64_t n[3];   /* voxels per axis (multiples of 8) */
    int64_t lo[3];  /* volume index of grid voxel (0,0,0) */
    int64_t words;  /* words per row */
    uint64_t *bits; /* n[0] * n[1] * words */
} hv_bitgrid;

hv_status hv_bitgrid_init(hv_bitgrid *g, const int64_t n[3], const int64_t lo[3]);
void hv_bitgrid_free(hv_bitgrid *g);
uint64_t hv_bitgrid_bytes(const int64_t n[3]);

static inline uint64_t *hv_bitgrid_row(const hv_bitgrid *g, int64_t i, int64_t j)
{
    return g->bits + (i * g->n[1] + j) * g->words;
}

static inline int hv_bitgrid_get(const hv_bitgrid *g, int64_t i, int64_t j, int64_t k)
{
    return (int)((hv_bitgrid_row(g, i, j)[k >> 6] >> (k & 63)) & 1u);
}

static inline void hv_bitgrid_set_atomic(hv_bitgrid *g, int64_t i, int64_t j, int64_t k)
{
    __atomic_fetch_or(&hv_bitgrid_row(g, i, j)[k >> 6], 1ull << (k & 63), __ATOMIC_RELAXED);
}

/* Mask of the valid bits of word w of a row (the last word may be partial). */
static inline uint64_t hv_bitgrid_valid(const hv_bitgrid *g, int64_t w)
{
    int64_t rem = g->n[2] - 64 * w;
    return rem >= 64 ? ~0ull : rem <= 0 ? 0ull : (1ull << rem) - 1u;
}

#endif
