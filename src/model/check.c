/* src/model/check.c - a model is checked when it is loaded (issue 32 item 11): every voxel of the
 * occupancy has fractions that are finite, in [0, 1] and sum to 1 (Wu eq. 12, within what 16-bit
 * storage explains), and no fraction lies outside the occupancy. A file whose grids disagree (a
 * material grid moved, edited or cut by another tool) is refused naming the voxel, instead of
 * feeding probes, stacks and renders fractions that do not sum to 1. */
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/model.h"

#define CHECK_MAX_GRIDS 64 /* HV_MAX_MATERIALS */

typedef struct check_ctx {
    const hv_volume *v;
    int occ, m, g[CHECK_MAX_GRIDS];
    float tol;
    _Atomic size_t first_bad; /* the first leaf with a bad voxel (SIZE_MAX: none) */
} check_ctx;

/* The first bad voxel of leaf l: its offset in *off and why in *kind (1 outside the occupancy, 2
 * a fraction out of [0, 1], 3 a sum off 1); returns 0 when the leaf is fine. */
static int leaf_bad(const check_ctx *c, size_t l, unsigned *off, int *kind, double *value)
{
    const uint64_t *mask = hv_volume_leaf_mask(c->v, l), *occ = hv_volume_leaf_bool_c(c->v, c->occ, l);
    const float *f[CHECK_MAX_GRIDS];
    for (int q = 0; q < c->m; ++q) f[q] = hv_volume_leaf_float_c(c->v, c->g[q], l);
    for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
        if (!HV_BIT_GET(mask, n)) continue;
        int inside = (int)HV_BIT_GET(occ, n);
        double sum = 0;
        for (int q = 0; q < c->m; ++q) {
            float x = f[q][n];
            if (!inside && x != 0.0f) {
                *off = n, *kind = 1, *value = x;
                return 1;
            }
            if (!(x >= 0.0f && x <= 1.0f + c->tol)) {
                *off = n, *kind = 2, *value = x;
                return 1;
            }
            sum += x;
        }
        if (inside && fabs(sum - 1.0) > c->tol) {
            *off = n, *kind = 3, *value = sum;
            return 1;
        }
    }
    return 0;
}

static hv_status check_range(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    check_ctx *c = vctx;
    unsigned off;
    int kind;
    double value;
    for (size_t l = b; l < e && l < atomic_load(&c->first_bad); ++l)
        if (leaf_bad(c, l, &off, &kind, &value)) {
            size_t cur = atomic_load(&c->first_bad);
            while (l < cur && !atomic_compare_exchange_weak(&c->first_bad, &cur, l)) {}
            return HV_OK;
        }
    return HV_OK;
}

hv_status hv_model_check(const hv_volume *v)
{
    check_ctx c;
    memset(&c, 0, sizeof c);
    c.v = v;
    c.occ = hv_volume_grid_find(v, "occupancy");
    if (c.occ < 0 || hv_volume_grid_type(v, c.occ) != HV_GRID_BOOL) return HV_OK;
    for (int i = 0; i < hv_volume_grid_count(v) && c.m < CHECK_MAX_GRIDS; ++i)
        if (hv_volume_grid_type(v, i) == HV_GRID_FLOAT && strncmp(hv_volume_grid_name(v, i), "material.", 9) == 0)
            c.g[c.m++] = i;
    if (c.m == 0) return HV_OK; /* not graded: nothing to sum */
    /* 16-bit storage leaves each fraction within 2^-12 (hovox/volume.h); allow that per material */
    c.tol = (float)c.m / 4096.0f + 1e-5f;
    atomic_init(&c.first_bad, SIZE_MAX);
    hv_status s = hv_parallel_for(hv_volume_leaf_count(v), 16, check_range, &c, NULL, NULL);
    if (s != HV_OK) return s;
    size_t l = atomic_load(&c.first_bad);
    if (l == SIZE_MAX) return HV_OK;
    unsigned off;
    int kind;
    double value;
    leaf_bad(&c, l, &off, &kind, &value);
    const int32_t *o = hv_volume_leaf_origins(v) + 3 * l;
    double idx[3] = {o[0] + (double)(off >> 6), o[1] + (double)((off >> 3) & 7), o[2] + (double)(off & 7)}, w[3];
    hv_volume_index_to_world(v, idx, w);
    char where[160];
    snprintf(where, sizeof where, "voxel %.0f,%.0f,%.0f (at %g, %g, %g)", idx[0], idx[1], idx[2], w[0], w[1], w[2]);
    if (kind == 1)
        return hv_error_set(HV_ERR_BAD_INPUT,
                            "%s: the material grids do not match the occupancy: %s is outside it but holds a "
                            "fraction %g (its grids were moved or edited apart)",
                            hv_volume_name(v), where, value);
    if (kind == 2)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s holds a material fraction %g outside [0, 1]", hv_volume_name(v),
                            where, value);
    return hv_error_set(HV_ERR_BAD_INPUT,
                        "%s: the material fractions of %s sum to %g, not 1 (a material grid is missing there, or "
                        "the grids were moved or edited apart)",
                        hv_volume_name(v), where, value);
}
