/* slicing/slice_plan.c - layer height planning for the geometric slicer (Wu 2.4.1 "slicing
 * polygonal meshes with same thickness or adaptive layers"): uniform layers with a first-layer
 * height, and adaptive layers by the cusp-height criterion (Dolenc & Makela 1994). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "slice_internal.h"

struct hv_layer_plan {
    size_t n;
    hv_layer *layers;
};

size_t hv_layer_plan_count(const hv_layer_plan *p) { return p ? p->n : 0; }
const hv_layer *hv_layer_plan_layers(const hv_layer_plan *p) { return p ? p->layers : NULL; }

void hv_layer_plan_destroy(hv_layer_plan *p)
{
    if (!p) return;
    free(p->layers);
    free(p);
}

static hv_status plan_alloc(size_t n, hv_layer_plan **out)
{
    if (n > HV_LAYER_PLAN_MAX)
        return hv_error_set(HV_ERR_LIMIT, "layers: the plan would need %zu layers (at most %d)", n,
                            HV_LAYER_PLAN_MAX);
    hv_layer_plan *p = hv_calloc(1, sizeof *p);
    if (!p) return HV_ERR_NOMEM;
    p->layers = hv_malloc_array(HV_MAX(n, (size_t)1), sizeof *p->layers);
    if (!p->layers) {
        free(p);
        return HV_ERR_NOMEM;
    }
    p->n = n;
    *out = p;
    return HV_OK;
}

static void set_layer(hv_layer *L, double bottom, double top)
{
    L->bottom = bottom;
    L->top = top;
    L->z = 0.5 * (bottom + top);
}

hv_status hv_layer_plan_create(const hv_layer *layers, size_t n, hv_layer_plan **out)
{
    if (!out) return hv_error_set(HV_ERR_INVALID, "hv_layer_plan_create: out is NULL");
    *out = NULL;
    if (n && !layers) return hv_error_set(HV_ERR_INVALID, "hv_layer_plan_create: layers is NULL");
    for (size_t i = 0; i < n; ++i) {
        const hv_layer *L = &layers[i];
        if (!isfinite(L->bottom) || !isfinite(L->top) || !isfinite(L->z) || !(L->bottom < L->top) ||
            L->z < L->bottom || L->z > L->top)
            return hv_error_set(HV_ERR_INVALID,
                                "layers: layer %zu: need finite bottom < top and bottom <= z <= top "
                                "(bottom %g, z %g, top %g)",
                                i, L->bottom, L->z, L->top);
        if (i && !(L->z > layers[i - 1].z))
            return hv_error_set(HV_ERR_INVALID,
                                "layers: layer %zu: z %g does not increase (previous %g)", i, L->z,
                                layers[i - 1].z);
    }
    hv_status st = plan_alloc(n, out);
    if (st != HV_OK) return st;
    if (n) memcpy((*out)->layers, layers, n * sizeof *layers);
    return HV_OK;
}

hv_status hv_slicer_plan_uniform(const hv_slicer *s, double first, double height,
                                 hv_layer_plan **out)
{
    if (!out) return hv_error_set(HV_ERR_INVALID, "hv_slicer_plan_uniform: out is NULL");
    *out = NULL;
    if (!s) return hv_error_set(HV_ERR_INVALID, "hv_slicer_plan_uniform: slicer is NULL");
    return hv_layer_plan_uniform(s->info.bbox_min[2], s->info.bbox_max[2], first, height, out);
}

hv_status hv_layer_plan_uniform(double zlo, double zhi, double first, double height, hv_layer_plan **out)
{
    *out = NULL;
    if (!isfinite(zlo) || !isfinite(zhi) || zhi < zlo)
        return hv_error_set(HV_ERR_INVALID, "layers: the part's height range %g to %g is not one", zlo, zhi);
    if (!(height > 0) || !isfinite(height))
        return hv_error_set(HV_ERR_INVALID, "layers: layer height %g must be finite and > 0", height);
    if (!isfinite(first))
        return hv_error_set(HV_ERR_INVALID, "layers: first layer height %g is not finite", first);
    if (first <= 0) first = height;
    /* layer i >= 1 spans [zlo + first + (i-1) h, zlo + first + i h]; it exists while its
     * mid-height is below zhi */
    size_t n = 0;
    if (zlo + 0.5 * first < zhi) {
        double m = (zhi - zlo - first - 0.5 * height) / height; /* layers above the first ~ m */
        if (m > (double)HV_LAYER_PLAN_MAX)
            return hv_error_set(HV_ERR_LIMIT,
                                "layers: %.6g mm of mesh at %g mm layers would need %.0f layers "
                                "(at most %d)",
                                zhi - zlo, height, m + 1, HV_LAYER_PLAN_MAX);
        size_t k = m > 0 ? (size_t)ceil(m) : 0;
        /* settle the rounding with the exact predicate */
        while (k > 0 && !(zlo + first + (double)(k - 1) * height + 0.5 * height < zhi)) --k;
        while (zlo + first + (double)k * height + 0.5 * height < zhi) ++k;
        n = 1 + k;
    }
    hv_status st = plan_alloc(n, out);
    if (st != HV_OK) return st;
    hv_layer *L = (*out)->layers;
    for (size_t i = 0; i < n; ++i) {
        double b = i == 0 ? zlo : zlo + first + (double)(i - 1) * height;
        double t = i == 0 ? zlo + first : zlo + first + (double)i * height;
        set_layer(&L[i], b, t);
    }
    return HV_OK;
}

/* ---- adaptive ------------------------------------------------------------------------------ */

typedef struct tol_ctx {
    const hv_slicer *s;
    double cusp, hmax;
    double *tol; /* per position in s->order */
} tol_ctx;

/* Height tolerated by each facet: cusp / |n_z|, at least hmax for near-vertical facets and
 * degenerate ones (which constrain nothing). */
static hv_status tol_range(void *c, size_t b, size_t e, int t)
{
    (void)t;
    tol_ctx *x = c;
    const hv_slicer *s = x->s;
    for (size_t i = b; i < e; ++i) {
        const uint32_t *v = s->tri + 3 * (size_t)s->order[i];
        const double *p = s->xyz + 3 * (size_t)v[0], *q = s->xyz + 3 * (size_t)v[1],
                     *r = s->xyz + 3 * (size_t)v[2];
        double ux = q[0] - p[0], uy = q[1] - p[1], uz = q[2] - p[2];
        double wx = r[0] - p[0], wy = r[1] - p[1], wz = r[2] - p[2];
        double nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
        double len = sqrt(nx * nx + ny * ny + nz * nz);
        double tol = x->hmax;
        if (len > 0 && fabs(nz) * x->hmax > x->cusp * len) tol = x->cusp * len / fabs(nz);
        x->tol[i] = tol;
    }
    return HV_OK;
}

hv_status hv_slicer_plan_adaptive(const hv_slicer *s, double first, double hmin, double hmax,
                                  double cusp, hv_layer_plan **out)
{
    if (!out) return hv_error_set(HV_ERR_INVALID, "hv_slicer_plan_adaptive: out is NULL");
    *out = NULL;
    if (!s) return hv_error_set(HV_ERR_INVALID, "hv_slicer_plan_adaptive: slicer is NULL");
    if (!isfinite(hmin) || !isfinite(hmax) || !(hmin > 0) || !(hmin <= hmax))
        return hv_error_set(HV_ERR_INVALID,
                            "layers: adaptive heights need 0 < min <= max (min %g, max %g)", hmin,
                            hmax);
    if (!isfinite(first) || !isfinite(cusp))
        return hv_error_set(HV_ERR_INVALID, "layers: first layer %g and cusp %g must be finite",
                            first, cusp);
    if (cusp <= 0) cusp = hmin;
    double zlo = s->info.bbox_min[2], zhi = s->info.bbox_max[2];
    if ((zhi - zlo) / hmin > (double)HV_LAYER_PLAN_MAX)
        return hv_error_set(HV_ERR_LIMIT,
                            "layers: %.6g mm of mesh at %g mm minimum layers could need %.0f "
                            "layers (at most %d)",
                            zhi - zlo, hmin, (zhi - zlo) / hmin, HV_LAYER_PLAN_MAX);
    double *tol = hv_malloc_array(s->nf, sizeof *tol);
    if (!tol) return HV_ERR_NOMEM;
    tol_ctx tx = {s, cusp, hmax, tol};
    hv_status st = hv_parallel_for(s->nf, 8192, tol_range, &tx, NULL, "layers");
    if (st != HV_OK) {
        free(tol);
        return st;
    }
    size_t cap = 0, n = 0;
    hv_layer *L = NULL;
    double z = zlo;
    while (st == HV_OK) {
        double h = hmax;
        if (n == 0 && first > 0) {
            h = first;
        } else {
            /* h = min over facets f overlapping (z, z + hmax) of max(tol_f, zmin_f - z) */
            for (int c = 0; c < HV_SLICE_CLASSES; ++c) {
                if (s->class_start[c] == s->class_start[c + 1]) continue;
                double ext = s->class_ext[c];
                double a = z - ext - (ext + fabs(z)) * 1e-12 - DBL_MIN;
                size_t lo, hi;
                hv_slicer_class_range(s, c, a, z + hmax, &lo, &hi);
                for (size_t i = lo; i < hi; ++i) {
                    if (!(s->szmax[i] > z)) continue;
                    double bound = HV_MAX(tol[i], s->szmin[i] - z);
                    if (bound < h) h = bound;
                }
            }
            h = HV_MAX(h, hmin);
        }
        if (!(z + 0.5 * h < zhi)) break;
        if (!(z + h > z)) {
            st = hv_error_set(HV_ERR_INVALID,
                              "layers: layer height %g is below the resolution of z = %g", h, z);
            break;
        }
        if (n + 1 > cap) st = hv_grow((void **)&L, &cap, n + 1, sizeof *L);
        if (st != HV_OK) break;
        set_layer(&L[n], z, z + h);
        z += h;
        ++n;
    }
    free(tol);
    if (st == HV_OK) st = plan_alloc(n, out);
    if (st == HV_OK && n) memcpy((*out)->layers, L, n * sizeof *L);
    free(L);
    return st;
}
