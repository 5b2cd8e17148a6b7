/* volumes/dense.c - grids of the sparse store copied into dense arrays over an index box (for
 * front ends that hand arrays to numerical code: the Python package's model.fractions()). The
 * box is cut into slabs of 8 x-planes, each zeroed and filled from its leaves by one thread, so
 * the array's pages are first touched by the thread that fills them. */
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

static hv_status dense_slabs(void *ctx, size_t begin, size_t end, int thread)
{
    (void)thread;
    const dense_job *j = ctx;
    const int32_t *org = hv_volume_leaf_origins(j->vol);
    size_t plane = j->ny * j->nz, per = j->mask ? 1 : (size_t)j->n;
    for (size_t s = begin; s < end; ++s) {
        int32_t xa, xb;
        slab_planes(j, s, &xa, &xb);
        if (xa >= xb) continue;
        size_t first = (size_t)(xa - j->lo[0]) * plane * per, count = (size_t)(xb - xa) * plane * per;
        if (j->mask) memset(j->mask + first, 0, count);
        else memset(j->out + first, 0, count * sizeof(float));
        for (size_t q = j->slab_first[s]; q < j->slab_first[s + 1]; ++q) {
            size_t l = j->order[q];
            const int32_t *o = org + 3 * l;
            const uint64_t *act = hv_volume_leaf_mask(j->vol, l);
            const uint64_t *bits = j->mask && j->g >= 0 ? hv_volume_leaf_bool_c(j->vol, j->g, l) : NULL;
            const float *buf[64];
            for (int c = 0; !j->mask && c < j->n; ++c) buf[c] = hv_volume_leaf_float_c(j->vol, j->grids[c], l);
            int32_t ya = HV_MAX(o[1], j->lo[1]), yb = HV_MIN(o[1] + 8, j->hi[1] + 1);
            int32_t za = HV_MAX(o[2], j->lo[2]), zb = HV_MIN(o[2] + 8, j->hi[2] + 1);
            int32_t xla = HV_MAX(o[0], xa), xlb = HV_MIN(o[0] + 8, xb);
            for (int32_t x = xla; x < xlb; ++x)
                for (int32_t y = ya; y < yb; ++y) {
                    size_t row = ((size_t)(x - j->lo[0]) * j->ny + (size_t)(y - j->lo[1])) * j->nz;
                    for (int32_t z = za; z < zb; ++z) {
                        unsigned n = HV_LEAF_OFFSET(x, y, z);
                        if (!HV_BIT_GET(act, n)) continue;
                        size_t at = row + (size_t)(z - j->lo[2]);
                        if (j->mask) {
                            j->mask[at] = (uint8_t)(bits ? HV_BIT_GET(bits, n) : 1u);
                        } else {
                            float *dst = j->out + at * per;
                            for (int c = 0; c < j->n; ++c) dst[c] = buf[c][n];
                        }
                    }
                }
        }
    }
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
