/* src/io/scan/level.c - the shape of a scan as a level function g >= 0 inside, evaluated at world
 * points by trilinear interpolation of the samples (not blocky thresholding): an iso value
 * (g = f - iso), a value range (g = min(f - lo, hi - f)), or a label set of a segmentation
 * (g = the trilinear interpolation of the indicator "sample's label is in the set" - 1/2, so
 * labels are never averaged into each other). Outside the samples' cells g is negative; between
 * the outermost sample centres and the cell faces the edge samples hold (clamped). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/scan/scan_internal.h"

static int cmp_i32(const void *a, const void *b)
{
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return x < y ? -1 : x > y;
}

hv_status hv_scan_level_init(const hv_scan *scan, const hv_scan_shape *shape, hv_scan_level *lv)
{
    memset(lv, 0, sizeof *lv);
    lv->scan = scan;
    lv->shape = *shape;
    for (int a = 0; a < 3; ++a) lv->n[a] = (int64_t)scan->dims[a];
    /* the inverse of the affine's 3x3 part */
    const double *m = scan->m;
    double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
                 m[2] * (m[4] * m[9] - m[5] * m[8]);
    double *v = lv->inv;
    v[0] = (m[5] * m[10] - m[6] * m[9]) / det;
    v[1] = (m[2] * m[9] - m[1] * m[10]) / det;
    v[2] = (m[1] * m[6] - m[2] * m[5]) / det;
    v[3] = (m[6] * m[8] - m[4] * m[10]) / det;
    v[4] = (m[0] * m[10] - m[2] * m[8]) / det;
    v[5] = (m[2] * m[4] - m[0] * m[6]) / det;
    v[6] = (m[4] * m[9] - m[5] * m[8]) / det;
    v[7] = (m[1] * m[8] - m[0] * m[9]) / det;
    v[8] = (m[0] * m[5] - m[1] * m[4]) / det;
    switch (shape->select) {
    case HV_SCAN_SELECT_ISO:
        if (!isfinite(shape->iso)) return hv_error_option(HV_ERR_INVALID, "{iso} must be a finite number");
        break;
    case HV_SCAN_SELECT_RANGE:
        if (!isfinite(shape->range[0]) || !isfinite(shape->range[1]) || shape->range[0] > shape->range[1])
            return hv_error_option(HV_ERR_INVALID, "{range} must be LO,HI with LO <= HI, got %g,%g", shape->range[0],
                                   shape->range[1]);
        break;
    case HV_SCAN_SELECT_LABELS:
        if (!shape->labels || shape->label_count == 0 || shape->label_count > 65536)
            return hv_error_option(HV_ERR_INVALID, "{labels} must name 1 to 65536 labels");
        lv->labels = hv_malloc_array(shape->label_count, sizeof *lv->labels);
        if (!lv->labels) return HV_ERR_NOMEM;
        memcpy(lv->labels, shape->labels, shape->label_count * sizeof *lv->labels);
        qsort(lv->labels, shape->label_count, sizeof *lv->labels, cmp_i32);
        lv->shape.labels = lv->labels;
        break;
    default: return hv_error_set(HV_ERR_INVALID, "scan shape: unknown selection %d", (int)shape->select);
    }
    return HV_OK;
}

void hv_scan_level_free(hv_scan_level *lv)
{
    free(lv->labels);
    lv->labels = NULL;
}

void hv_scan_level_index(const hv_scan_level *lv, const double world[3], double idx[3])
{
    const double *m = lv->scan->m;
    double d[3] = {world[0] - m[3], world[1] - m[7], world[2] - m[11]};
    for (int r = 0; r < 3; ++r) idx[r] = lv->inv[3 * r] * d[0] + lv->inv[3 * r + 1] * d[1] + lv->inv[3 * r + 2] * d[2];
}

static inline double member(const hv_scan_level *lv, float v)
{
    double r = rint((double)v);
    if (r != (double)v || fabs(r) > 2147483647.0) return 0;
    int32_t key = (int32_t)r;
    return bsearch(&key, lv->labels, lv->shape.label_count, sizeof key, cmp_i32) ? 1.0 : 0.0;
}

static inline double to_level(const hv_scan_level *lv, double f)
{
    switch (lv->shape.select) {
    case HV_SCAN_SELECT_ISO: return f - lv->shape.iso;
    case HV_SCAN_SELECT_RANGE: return fmin(f - lv->shape.range[0], lv->shape.range[1] - f);
    default: return f - 0.5;
    }
}

double hv_scan_level_at_index(const hv_scan_level *lv, const double idx[3])
{
    int64_t i0[3];
    double t[3];
    for (int a = 0; a < 3; ++a) {
        double x = idx[a];
        if (!(x >= -0.5 && x <= (double)lv->n[a] - 0.5)) return -INFINITY;
        x = HV_CLAMP(x, 0.0, (double)(lv->n[a] - 1));
        int64_t i = (int64_t)floor(x);
        if (i > lv->n[a] - 2) i = lv->n[a] - 2;
        if (i < 0) i = 0;
        i0[a] = i;
        t[a] = lv->n[a] > 1 ? x - (double)i : 0;
    }
    const float *d = lv->scan->data;
    size_t nx = (size_t)lv->n[0], nxy = nx * (size_t)lv->n[1];
    int sx = lv->n[0] > 1, sy = lv->n[1] > 1, sz = lv->n[2] > 1;
    size_t base = (size_t)i0[0] + nx * (size_t)i0[1] + nxy * (size_t)i0[2];
    size_t ox = (size_t)sx, oy = sy ? nx : 0, oz = sz ? nxy : 0;
    double c[8];
    const size_t off[8] = {0, ox, oy, ox + oy, oz, ox + oz, oy + oz, ox + oy + oz};
    for (int k = 0; k < 8; ++k) {
        float v = d[base + off[k]];
        c[k] = lv->shape.select == HV_SCAN_SELECT_LABELS ? member(lv, v) : (double)v;
    }
    double x0 = c[0] + (c[1] - c[0]) * t[0], x1 = c[2] + (c[3] - c[2]) * t[0];
    double x2 = c[4] + (c[5] - c[4]) * t[0], x3 = c[6] + (c[7] - c[6]) * t[0];
    double y0 = x0 + (x1 - x0) * t[1], y1 = x2 + (x3 - x2) * t[1];
    return to_level(lv, y0 + (y1 - y0) * t[2]);
}

double hv_scan_level_at(const hv_scan_level *lv, const double world[3])
{
    double idx[3];
    hv_scan_level_index(lv, world, idx);
    return hv_scan_level_at_index(lv, idx);
}

/* ---- the inside's box ------------------------------------------------------------------------ */

/* g at sample (i, j, k): the sample's own level (trilinear interpolation at a sample centre is the
 * sample), through the interpolation itself on the last sample of an axis, where it weighs the
 * last two samples by 0 and 1. */
static inline double level_at_sample(const hv_scan_level *lv, int64_t i, int64_t j, int64_t k)
{
    if (i == lv->n[0] - 1 || j == lv->n[1] - 1 || k == lv->n[2] - 1) {
        double idx[3] = {(double)i, (double)j, (double)k};
        return hv_scan_level_at_index(lv, idx);
    }
    float v = lv->scan->data[(size_t)i + (size_t)lv->n[0] * ((size_t)j + (size_t)lv->n[1] * (size_t)k)];
    return to_level(lv, lv->shape.select == HV_SCAN_SELECT_LABELS ? member(lv, v) : (double)v);
}

typedef struct box_ctx {
    const hv_scan_level *lv;
    double *box; /* 6 per k: lo[3], hi[3] */
} box_ctx;

/* Samples of layers k in [b, e): every inside sample toward each outside neighbour, the point
 * where the field crosses (half a sample beyond the last sample of the data), through the affine.
 * Toward an inside neighbour the point would be that neighbour, which lies between its own
 * crossings: those bound the box already. */
static hv_status box_range(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    box_ctx *c = vctx;
    const hv_scan_level *lv = c->lv;
    const int64_t *n = lv->n;
    const double *m = lv->scan->m;
    for (size_t kk = b; kk < e; ++kk) {
        int64_t k = (int64_t)kk;
        double *lo = c->box + 6 * kk, *hi = lo + 3;
        for (int r = 0; r < 3; ++r) lo[r] = INFINITY, hi[r] = -INFINITY;
        for (int64_t j = 0; j < n[1]; ++j)
            for (int64_t i = 0; i < n[0]; ++i) {
                double g = level_at_sample(lv, i, j, k);
                if (g < 0) continue;
                int64_t at[3] = {i, j, k};
                for (int a = 0; a < 3; ++a)
                    for (int dir = -1; dir <= 1; dir += 2) {
                        int64_t q[3] = {i, j, k};
                        q[a] += dir;
                        double ge = q[a] < 0 || q[a] > n[a] - 1 ? -INFINITY : level_at_sample(lv, q[0], q[1], q[2]);
                        if (ge >= 0) continue;
                        double reach = isinf(ge) ? 0.5 : g / (g - ge);
                        double x[3] = {(double)at[0], (double)at[1], (double)at[2]};
                        x[a] += dir * reach;
                        for (int r = 0; r < 3; ++r) {
                            double w = m[4 * r] * x[0] + m[4 * r + 1] * x[1] + m[4 * r + 2] * x[2] + m[4 * r + 3];
                            lo[r] = fmin(lo[r], w);
                            hi[r] = fmax(hi[r], w);
                        }
                    }
            }
    }
    return HV_OK;
}

hv_status hv_scan_inside_box(const hv_scan_level *lv, double lo[3], double hi[3])
{
    for (int r = 0; r < 3; ++r) lo[r] = INFINITY, hi[r] = -INFINITY;
    size_t nk = (size_t)lv->n[2];
    box_ctx c = {lv, hv_malloc_array(nk, 6 * sizeof(double))};
    if (!c.box) return HV_ERR_NOMEM;
    hv_status st = hv_parallel_for(nk, 1, box_range, &c, NULL, "box");
    for (size_t k = 0; k < nk && st == HV_OK; ++k)
        for (int r = 0; r < 3; ++r) {
            lo[r] = fmin(lo[r], c.box[6 * k + r]);
            hi[r] = fmax(hi[r], c.box[6 * k + 3 + r]);
        }
    free(c.box);
    if (st == HV_OK && !(lo[0] <= hi[0])) { /* empty */
        memset(lo, 0, 3 * sizeof *lo);
        memset(hi, 0, 3 * sizeof *hi);
    }
    return st;
}
