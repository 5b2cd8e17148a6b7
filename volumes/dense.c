/* volumes/dense.c - grids of the sparse store copied into dense arrays over an index box (for
 * front ends that hand arrays to numerical code: the Python package's model.fractions()). The
 * box is cut into slabs of 8 x-planes, each written by one thread (so the array's pages are first
 * touched by the thread that fills them), every value once: from its leaf, or 0. */
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/volume.h"

typedef struct dense_job {
    const hv_volume *vol;
    const int *grids;     /* n grids (dense_float) */
    int n;
    int g;                /* dense_mask: a bool grid, or -1 for the active voxels */
    int32_t lo[3], hi[3];
    size_t ny, nz;
    float *out;           /* dense_float */
    uint8_t *mask;        /* dense_mask */
    const size_t *slab_first; /* leaves of slab s: order[slab_first[s] .. slab_first[s + 1]) */
    const size_t *order;
    int32_t slab0;        /* x of slab 0's first plane, a multiple of 8 */
} dense_job;

/* The x-planes of slab s that lie in the box: [*a, *b). */
static void slab_planes(const dense_job *j, size_t s, int32_t *a, int32_t *b)
{
    int32_t x0 = j->slab0 + 8 * (int32_t)s;
    *a = HV_MAX(x0, j->lo[0]);
    *b = HV_MIN(x0 + 8, j->hi[0] + 1);
}

/* One slab: every value of its x-planes written once, row by row (y), in runs of up to 8 z: from
 * the leaf that holds the run (its active mask decides value or 0), else zeros. */
static hv_status dense_slabs(void *ctx, size_t begin, size_t end, int thread)
{
    (void)thread;
    const dense_job *j = ctx;
    const int32_t *org = hv_volume_leaf_origins(j->vol);
    size_t per = j->mask ? 1 : (size_t)j->n;
    int32_t ty0 = j->lo[1] & ~7, tz0 = j->lo[2] & ~7;
    size_t nty = (size_t)(((int64_t)j->hi[1] - ty0) / 8 + 1), ntz = (size_t)(((int64_t)j->hi[2] - tz0) / 8 + 1);
    int64_t *tile = hv_malloc_array(nty * ntz, sizeof *tile); /* the leaf of each (y, z) tile, or -1 */
    if (!tile) return HV_ERR_NOMEM;
    for (size_t s = begin; s < end; ++s) {
        int32_t xa, xb;
        slab_planes(j, s, &xa, &xb);
        if (xa >= xb) continue;
        for (size_t t = 0; t < nty * ntz; ++t) tile[t] = -1;
        for (size_t q = j->slab_first[s]; q < j->slab_first[s + 1]; ++q) {
            size_t l = j->order[q];
            tile[(size_t)((org[3 * l + 1] - ty0) / 8) * ntz + (size_t)((org[3 * l + 2] - tz0) / 8)] = (int64_t)l;
        }
        for (int32_t x = xa; x < xb; ++x)
            for (int32_t y = j->lo[1]; y <= j->hi[1]; ++y) {
                size_t row = ((size_t)(x - j->lo[0]) * j->ny + (size_t)(y - j->lo[1])) * j->nz;
                const int64_t *trow = tile + (size_t)((y - ty0) / 8) * ntz;
                for (size_t tz = 0; tz < ntz; ++tz) {
                    int32_t z0 = tz0 + 8 * (int32_t)tz, za = HV_MAX(z0, j->lo[2]), zb = HV_MIN(z0 + 8, j->hi[2] + 1);
                    size_t at = row + (size_t)(za - j->lo[2]), len = (size_t)(zb - za);
                    int64_t l = trow[tz];
                    if (l < 0) {
                        if (j->mask) memset(j->mask + at, 0, len);
                        else memset(j->out + at * per, 0, len * per * sizeof(float));
                        continue;
                    }
                    /* the run's active bits: bits (y & 7) * 8 .. + 7 of word x & 7 */
                    unsigned act = (unsigned)(hv_volume_leaf_mask(j->vol, (size_t)l)[x & 7] >> (8 * (y & 7))) & 0xffu;
                    unsigned base = ((unsigned)(x & 7) << 6) | ((unsigned)(y & 7) << 3);
                    if (j->mask) {
                        const uint64_t *bits = j->g >= 0 ? hv_volume_leaf_bool_c(j->vol, j->g, (size_t)l) : NULL;
                        unsigned on = bits ? act & (unsigned)(bits[x & 7] >> (8 * (y & 7))) : act;
                        for (int32_t z = za; z < zb; ++z) j->mask[at + (size_t)(z - za)] = (uint8_t)((on >> (z & 7)) & 1u);
                        continue;
                    }
                    float *dst = j->out + at * per;
                    for (int c = 0; c < j->n; ++c) {
                        const float *src = hv_volume_leaf_float_c(j->vol, j->grids[c], (size_t)l) + base;
                        if (act == 0xffu)
                            for (int32_t z = za; z < zb; ++z) dst[(size_t)(z - za) * per + (size_t)c] = src[z & 7];
                        else
                            for (int32_t z = za; z < zb; ++z)
                                dst[(size_t)(z - za) * per + (size_t)c] = (act >> (z & 7)) & 1u ? src[z & 7] : 0.0f;
                    }
                }
            }
    }
    free(tile);
    return HV_OK;
}

/* Sort the leaves that meet the box into slabs of 8 x-planes (a counting sort) and run. */
static hv_status dense_run(dense_job *j)
{
    for (int a = 0; a < 3; ++a)
        if (j->hi[a] < j->lo[a]) return hv_error_set(HV_ERR_INVALID, "empty index box");
    j->ny = (size_t)((int64_t)j->hi[1] - j->lo[1] + 1);
    j->nz = (size_t)((int64_t)j->hi[2] - j->lo[2] + 1);
    j->slab0 = j->lo[0] & ~7;
    size_t nslabs = (size_t)(((int64_t)j->hi[0] - j->slab0) / 8 + 1);
    size_t nl = hv_volume_leaf_count(j->vol);
    const int32_t *org = hv_volume_leaf_origins(j->vol);
    size_t *first = hv_calloc(nslabs + 1, sizeof *first), *order = hv_malloc_array(nl ? nl : 1, sizeof *order);
    if (!first || !order) {
        free(first);
        free(order);
        return HV_ERR_NOMEM;
    }
#define MEETS(o) \
    ((o)[0] + 7 >= j->lo[0] && (o)[0] <= j->hi[0] && (o)[1] + 7 >= j->lo[1] && (o)[1] <= j->hi[1] && \
     (o)[2] + 7 >= j->lo[2] && (o)[2] <= j->hi[2])
    for (size_t l = 0; l < nl; ++l)
        if (MEETS(org + 3 * l)) ++first[(size_t)((org[3 * l] - j->slab0) / 8) + 1];
    for (size_t s = 0; s < nslabs; ++s) first[s + 1] += first[s];
    size_t *fill = hv_malloc_array(nslabs, sizeof *fill);
    if (!fill) {
        free(first);
        free(order);
        return HV_ERR_NOMEM;
    }
    memcpy(fill, first, nslabs * sizeof *fill);
    for (size_t l = 0; l < nl; ++l)
        if (MEETS(org + 3 * l)) order[fill[(size_t)((org[3 * l] - j->slab0) / 8)]++] = l;
#undef MEETS
    free(fill);
    j->slab_first = first;
    j->order = order;
    hv_status s = hv_parallel_for(nslabs, 1, dense_slabs, j, NULL, "dense");
    free(first);
    free(order);
    return s;
}

hv_status hv_volume_dense(const hv_volume *vol, const int *grids, int n, const int32_t lo[3], const int32_t hi[3],
                          float *out)
{
    if (n < 1 || n > 64) return hv_error_set(HV_ERR_INVALID, "dense: %d grids (1 to 64)", n);
    for (int c = 0; c < n; ++c)
        if (grids[c] < 0 || grids[c] >= hv_volume_grid_count(vol) || hv_volume_grid_type(vol, grids[c]) != HV_GRID_FLOAT)
            return hv_error_set(HV_ERR_INVALID, "dense: grid %d is not a float grid of the volume", grids[c]);
    dense_job j = {.vol = vol, .grids = grids, .n = n, .g = -1, .out = out};
    memcpy(j.lo, lo, sizeof j.lo);
    memcpy(j.hi, hi, sizeof j.hi);
    return dense_run(&j);
}

hv_status hv_volume_dense_mask(const hv_volume *vol, int g, const int32_t lo[3], const int32_t hi[3], uint8_t *out)
{
    if (g >= 0 && (g >= hv_volume_grid_count(vol) || hv_volume_grid_type(vol, g) != HV_GRID_BOOL))
        return hv_error_set(HV_ERR_INVALID, "dense: grid %d is not a bool grid of the volume", g);
    dense_job j = {.vol = vol, .g = g < 0 ? -1 : g, .mask = out};
    memcpy(j.lo, lo, sizeof j.lo);
    memcpy(j.hi, hi, sizeof j.hi);
    return dense_run(&j);
}
