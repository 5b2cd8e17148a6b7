/* src/material/frf.c - fixed reference features (Wu 2.2.2: "the unmovable feature(s) are
 * called fixed reference feature(s)") and their distance fields. Analytic features (point,
 * line, plane, segment) are evaluated exactly per voxel; voxel features (the model's contour,
 * a mask, a facet group, a harmonic field between facet groups) are computed once per lattice
 * box with the exact Euclidean distance transform (Felzenszwalb-Huttenlocher 2012, src/field)
 * or the Laplace solver, and cached: Wu fixes the features precisely because these fields are
 * expensive. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "voxel/bitgrid.h"
#include "voxel/voxel_internal.h"
#include "field/field_internal.h"
#include "material_internal.h"

double hv_voxel_scale(const hv_transform *xf) { return cbrt(xf->voxel[0] * xf->voxel[1] * xf->voxel[2]); }

static hv_status new_frf(hv_frf_kind kind, hv_frf **out)
{
    hv_frf *f = hv_calloc(1, sizeof *f);
    if (!f) return HV_ERR_NOMEM;
    f->refs = 1;
    f->kind = kind;
    pthread_mutex_init(&f->lock, NULL);
    *out = f;
    return HV_OK;
}

static int finite3(const double v[3]) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }

static int unit3(const double v[3], double u[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(l > 0) || !isfinite(l)) return 0;
    for (int i = 0; i < 3; ++i) u[i] = v[i] / l;
    return 1;
}

hv_status hv_frf_point(const double p[3], hv_frf **out)
{
    *out = NULL;
    if (!finite3(p)) return hv_error_set(HV_ERR_INVALID, "point feature: coordinates must be finite");
    hv_status s = new_frf(HV_FRF_POINT, out);
    if (s != HV_OK) return s;
    memcpy((*out)->a, p, 3 * sizeof(double));
    snprintf((*out)->desc, sizeof (*out)->desc, "point(%.9g,%.9g,%.9g)", p[0], p[1], p[2]);
    return HV_OK;
}

hv_status hv_frf_line(const double o[3], const double dir[3], hv_frf **out)
{
    *out = NULL;
    double u[3];
    if (!finite3(o) || !unit3(dir, u))
        return hv_error_set(HV_ERR_INVALID, "axis feature: origin must be finite and direction non-zero");
    hv_status s = new_frf(HV_FRF_LINE, out);
    if (s != HV_OK) return s;
    memcpy((*out)->a, o, 3 * sizeof(double));
    memcpy((*out)->b, u, 3 * sizeof(double));
    snprintf((*out)->desc, sizeof (*out)->desc, "axis(%.9g,%.9g,%.9g; %.9g,%.9g,%.9g)", o[0], o[1], o[2],
             dir[0], dir[1], dir[2]);
    return HV_OK;
}

hv_status hv_frf_plane(const double p[3], const double n[3], hv_frf **out)
{
    *out = NULL;
    double u[3];
    if (!finite3(p) || !unit3(n, u))
        return hv_error_set(HV_ERR_INVALID, "plane feature: point must be finite and normal non-zero");
    hv_status s = new_frf(HV_FRF_PLANE, out);
    if (s != HV_OK) return s;
    memcpy((*out)->a, p, 3 * sizeof(double));
    memcpy((*out)->b, u, 3 * sizeof(double));
    snprintf((*out)->desc, sizeof (*out)->desc, "plane(%.9g,%.9g,%.9g; %.9g,%.9g,%.9g)", p[0], p[1], p[2],
             n[0], n[1], n[2]);
    return HV_OK;
}

hv_status hv_frf_halfspace(const double p[3], const double n[3], hv_frf **out)
{
    *out = NULL;
    double u[3];
    if (!finite3(p) || !unit3(n, u))
        return hv_error_set(HV_ERR_INVALID, "halfspace feature: point must be finite and normal non-zero");
    hv_status s = new_frf(HV_FRF_HALFSPACE, out);
    if (s != HV_OK) return s;
    memcpy((*out)->a, p, 3 * sizeof(double));
    memcpy((*out)->b, u, 3 * sizeof(double));
    snprintf((*out)->desc, sizeof (*out)->desc, "halfspace(%.9g,%.9g,%.9g; %.9g,%.9g,%.9g)", p[0], p[1], p[2],
             n[0], n[1], n[2]);
    return HV_OK;
}

hv_status hv_frf_segment(const double a[3], const double b[3], hv_frf **out)
{
    *out = NULL;
    if (!finite3(a) || !finite3(b)) return hv_error_set(HV_ERR_INVALID, "segment feature: ends must be finite");
    hv_status s = new_frf(HV_FRF_SEGMENT, out);
    if (s != HV_OK) return s;
    memcpy((*out)->a, a, 3 * sizeof(double));
    memcpy((*out)->b, b, 3 * sizeof(double));
    snprintf((*out)->desc, sizeof (*out)->desc, "segment(%.9g,%.9g,%.9g; %.9g,%.9g,%.9g)", a[0], a[1], a[2],
             b[0], b[1], b[2]);
    return HV_OK;
}

/* A volume holding just bool grid `grid` of vol, restricted to its true voxels. */
static hv_status copy_mask(const hv_volume *vol, const char *grid, hv_volume **out)
{
    *out = NULL;
    int g = hv_volume_grid_need(vol, grid, HV_GRID_BOOL);
    if (g < 0) return hv_error_prefix(HV_ERR_NOT_FOUND, "the model has ");
    hv_transform xf = hv_volume_get_transform(vol);
    hv_volume *m;
    hv_status s = hv_volume_create(&xf, &m);
    if (s != HV_OK) return s;
    if ((s = hv_volume_grid_copy(m, "mask", vol, g)) != HV_OK ||
        (s = hv_volume_topology_restrict(m, 0)) != HV_OK) {
        hv_volume_destroy(m);
        return s;
    }
    if (hv_volume_active_count(m) == 0) {
        hv_volume_destroy(m);
        return hv_error_set(HV_ERR_INVALID, "bool grid '%s' is empty", grid);
    }
    *out = m;
    return HV_OK;
}

hv_status hv_frf_contour(const hv_volume *vol, const char *grid, hv_frf **out)
{
    *out = NULL;
    hv_volume *m;
    hv_status s = copy_mask(vol, grid, &m);
    if (s != HV_OK) return s;
    if ((s = new_frf(HV_FRF_CONTOUR, out)) != HV_OK) {
        hv_volume_destroy(m);
        return s;
    }
    (*out)->mask = m;
    snprintf((*out)->desc, sizeof (*out)->desc, "contour(%s)", grid);
    return HV_OK;
}

hv_status hv_frf_mask(const hv_volume *vol, const char *grid, hv_frf **out)
{
    *out = NULL;
    hv_volume *m;
    hv_status s = copy_mask(vol, grid, &m);
    if (s != HV_OK) return s;
    if ((s = new_frf(HV_FRF_MASK, out)) != HV_OK) {
        hv_volume_destroy(m);
        return s;
    }
    (*out)->mask = m;
    snprintf((*out)->desc, sizeof (*out)->desc, "mask(%s)", grid);
    return HV_OK;
}

static int facet_selected(const hv_mesh *mesh, size_t f, const hv_facet_select *sel)
{
    const float *v = hv_mesh_vertices(mesh);
    const uint32_t *t = hv_mesh_facets(mesh) + 3 * f;
    const float *a = v + 3 * (size_t)t[0], *b = v + 3 * (size_t)t[1], *c = v + 3 * (size_t)t[2];
    if (sel->use_normal) {
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        double ln = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        double ls = sqrt(sel->normal[0] * sel->normal[0] + sel->normal[1] * sel->normal[1] +
                         sel->normal[2] * sel->normal[2]);
        if (!(ln > 0) || !(ls > 0)) return 0;
        double cosang = (n[0] * sel->normal[0] + n[1] * sel->normal[1] + n[2] * sel->normal[2]) / (ln * ls);
        if (cosang < cos(sel->angle_deg * 3.14159265358979323846 / 180.0) - 1e-12) return 0;
    }
    if (sel->use_box)
        for (int k = 0; k < 3; ++k) {
            double cen = ((double)a[k] + b[k] + c[k]) / 3.0;
            if (cen < sel->box_lo[k] || cen > sel->box_hi[k]) return 0;
        }
    return 1;
}

size_t hv_facet_select_count(const hv_mesh *mesh, const hv_facet_select *sel)
{
    size_t n = 0;
    for (size_t f = 0; f < hv_mesh_facet_count(mesh); ++f) n += (size_t)facet_selected(mesh, f, sel);
    return n;
}

static hv_status copy_facets(const hv_mesh *mesh, const hv_facet_select *sel, float **tris, size_t *n)
{
    size_t count = hv_facet_select_count(mesh, sel);
    if (count == 0) return hv_error_set(HV_ERR_INVALID, "the facet selection picks no facet");
    float *t = hv_malloc_array(count, 9 * sizeof(float));
    if (!t) return HV_ERR_NOMEM;
    size_t k = 0;
    const float *v = hv_mesh_vertices(mesh);
    for (size_t f = 0; f < hv_mesh_facet_count(mesh); ++f) {
        if (!facet_selected(mesh, f, sel)) continue;
        for (int c = 0; c < 3; ++c)
            memcpy(t + 9 * k + 3 * (size_t)c, v + 3 * (size_t)hv_mesh_facets(mesh)[3 * f + (size_t)c],
                   3 * sizeof(float));
        ++k;
    }
    *tris = t;
    *n = count;
    return HV_OK;
}

hv_status hv_frf_facets(const hv_mesh *mesh, const hv_facet_select *sel, hv_frf **out)
{
    *out = NULL;
    float *t;
    size_t n;
    hv_status s = copy_facets(mesh, sel, &t, &n);
    if (s != HV_OK) return s;
    if ((s = new_frf(HV_FRF_FACETS, out)) != HV_OK) {
        free(t);
        return s;
    }
    (*out)->tris = t;
    (*out)->ntris = n;
    snprintf((*out)->desc, sizeof (*out)->desc, "facets(%zu)", n);
    return HV_OK;
}

hv_status hv_frf_harmonic(const hv_volume *vol, const char *domain, const hv_mesh *mesh,
                          const hv_facet_select *one, const hv_facet_select *zero, hv_frf **out)
{
    *out = NULL;
    hv_volume *m = NULL;
    float *t1 = NULL, *t0 = NULL;
    size_t n1 = 0, n0 = 0;
    hv_status s = copy_mask(vol, domain, &m);
    if (s == HV_OK) s = copy_facets(mesh, one, &t1, &n1);
    if (s == HV_OK) s = copy_facets(mesh, zero, &t0, &n0);
    if (s == HV_OK) s = new_frf(HV_FRF_HARMONIC, out);
    if (s != HV_OK) {
        hv_volume_destroy(m);
        free(t1);
        free(t0);
        return s;
    }
    (*out)->mask = m;
    (*out)->tris = t1;
    (*out)->ntris = n1;
    (*out)->tris0 = t0;
    (*out)->ntris0 = n0;
    snprintf((*out)->desc, sizeof (*out)->desc, "harmonic(%s; %zu facets = 1; %zu facets = 0)", domain, n1, n0);
    return HV_OK;
}

hv_frf *hv_frf_retain(hv_frf *f)
{
    if (f) __atomic_add_fetch(&f->refs, 1, __ATOMIC_RELAXED);
    return f;
}

void hv_frf_release(hv_frf *f)
{
    if (!f || __atomic_sub_fetch(&f->refs, 1, __ATOMIC_ACQ_REL) > 0) return;
    hv_volume_destroy(f->mask);
    hv_volume_destroy(f->src);
    free(f->tris);
    free(f->tris0);
    free(f->cache.d);
    pthread_mutex_destroy(&f->lock);
    free(f);
}

hv_frf_kind hv_frf_get_kind(const hv_frf *f) { return f->kind; }
const char *hv_frf_describe(const hv_frf *f) { return f->desc; }

static int is_voxel_kind(hv_frf_kind k)
{
    return k == HV_FRF_CONTOUR || k == HV_FRF_MASK || k == HV_FRF_FACETS || k == HV_FRF_HARMONIC;
}

int hv_frf_is_voxel(const hv_frf *f) { return is_voxel_kind(f->kind); }

int hv_frf_is_signed(const hv_frf *f) { return f->kind == HV_FRF_HALFSPACE || f->kind == HV_FRF_FIELD; }

/* Features evaluated from their parameters (and stored in a model as them). */
static int is_analytic_kind(hv_frf_kind k) { return k <= HV_FRF_SEGMENT || k == HV_FRF_HALFSPACE; }

hv_status hv_frf_field(const hv_volume *vol, const char *grid, const char *description, hv_frf **out)
{
    *out = NULL;
    int g = hv_volume_grid_find(vol, grid);
    if (g < 0 || hv_volume_grid_type(vol, g) != HV_GRID_FLOAT)
        return hv_error_set(HV_ERR_BAD_INPUT, "the model has no float grid '%s' (a stored distance field)", grid);
    hv_transform xf = hv_volume_get_transform(vol);
    hv_volume *v;
    hv_status s = hv_volume_create(&xf, &v);
    if (s != HV_OK) return s;
    if ((s = hv_volume_grid_copy(v, "d", vol, g)) != HV_OK || (s = new_frf(HV_FRF_FIELD, out)) != HV_OK) {
        hv_volume_destroy(v);
        return s;
    }
    (*out)->mask = v;
    snprintf((*out)->desc, sizeof (*out)->desc, "%s", description && *description ? description : grid);
    return HV_OK;
}

/* ---- voxel fields ------------------------------------------------------------------------- */

/* Grow [lo, lo+n) to include the index bbox of mask volume m (same lattice). */
static void include_mask(const hv_volume *m, int64_t lo[3], int64_t hi[3])
{
    int32_t a[3], b[3];
    if (!hv_volume_index_bbox(m, a, b)) return;
    for (int k = 0; k < 3; ++k) {
        lo[k] = HV_MIN(lo[k], (int64_t)a[k]);
        hi[k] = HV_MAX(hi[k], (int64_t)b[k]);
    }
}

static void include_tris(const float *t, size_t n, const hv_transform *xf, int64_t lo[3], int64_t hi[3])
{
    for (size_t i = 0; i < 3 * n; ++i)
        for (int k = 0; k < 3; ++k) {
            double u = ((double)t[3 * i + (size_t)k] - xf->origin[k]) / xf->voxel[k];
            lo[k] = HV_MIN(lo[k], (int64_t)floor(u) - 1);
            hi[k] = HV_MAX(hi[k], (int64_t)ceil(u) + 1);
        }
}

/* Set feature[v] = 1 for voxels of the box that the triangles touch (thin, adjacency 6). */
static hv_status rasterize(const float *t, size_t n, const hv_transform *xf, const int64_t lo[3],
                           const int64_t dims[3], uint8_t *feature, uint8_t value)
{
    hv_bitgrid g;
    int64_t zero[3] = {0, 0, 0};
    hv_status s = hv_bitgrid_init(&g, dims, zero);
    if (s != HV_OK) return s;
    for (size_t i = 0; i < n; ++i) {
        double q[3][3];
        const double *p[3] = {q[0], q[1], q[2]};
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k)
                q[c][k] = ((double)t[9 * i + 3 * (size_t)c + (size_t)k] - xf->origin[k]) / xf->voxel[k] - (double)lo[k];
        hv_voxel_mark_triangle(p, 0, &g);
    }
    for (int64_t i = 0; i < dims[0]; ++i)
        for (int64_t j = 0; j < dims[1]; ++j)
            for (int64_t k = 0; k < dims[2]; ++k)
                if (hv_bitgrid_get(&g, i, j, k)) feature[(i * dims[1] + j) * dims[2] + k] = value;
    hv_bitgrid_free(&g);
    return HV_OK;
}

typedef struct stamp_ctx {
    const hv_volume *m;
    const int64_t *lo, *n;
    uint8_t *feature, value, fill;
} stamp_ctx;

/* fill x slabs [b, e) of the box (first touch of the pages on the threads that stamp them) */
static hv_status fill_slabs(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    const stamp_ctx *c = vctx;
    size_t slab = (size_t)(c->n[1] * c->n[2]);
    memset(c->feature + b * slab, c->fill, (e - b) * slab);
    return HV_OK;
}

/* leaves [b, e): set their true voxels; leaves are disjoint, so threads never share a byte */
static hv_status stamp_leaves(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    const stamp_ctx *c = vctx;
    const int32_t *org = hv_volume_leaf_origins(c->m);
    const int64_t *lo = c->lo, *n = c->n;
    for (size_t l = b; l < e; ++l) {
        const uint64_t *mask = hv_volume_leaf_mask(c->m, l);
        const uint64_t *val = hv_volume_leaf_bool_c(c->m, 0, l);
        for (unsigned w = 0; w < HV_LEAF_WORDS; ++w)
            for (uint64_t bits = mask[w] & val[w]; bits; bits &= bits - 1) {
                unsigned q = 64 * w + (unsigned)__builtin_ctzll(bits);
                int64_t i = org[3 * l] + (int64_t)(q >> 6) - lo[0], j = org[3 * l + 1] + (int64_t)((q >> 3) & 7) - lo[1],
                        k = org[3 * l + 2] + (int64_t)(q & 7) - lo[2];
                if (i < 0 || j < 0 || k < 0 || i >= n[0] || j >= n[1] || k >= n[2]) continue;
                c->feature[(i * n[1] + j) * n[2] + k] = c->value;
            }
    }
    return HV_OK;
}

/* feature[] = fill over the box, then value where the mask (if any) is true (mask in box
 * coordinates). */
static hv_status stamp_mask(const hv_volume *m, const int64_t lo[3], const int64_t n[3], uint8_t *feature,
                            uint8_t fill, uint8_t value)
{
    stamp_ctx c = {m, lo, n, feature, value, fill};
    hv_status s = hv_parallel_for((size_t)n[0], 4, fill_slabs, &c, NULL, "field");
    return s == HV_OK && m ? hv_parallel_for(hv_volume_leaf_count(m), 256, stamp_leaves, &c, NULL, "field") : s;
}

static hv_status compute_field(hv_frf *f, const hv_transform *xf, const int64_t want_lo[3],
                               const int64_t want_n[3], const hv_progress *progress)
{
    int64_t lo[3], hi[3], n[3];
    for (int k = 0; k < 3; ++k) {
        lo[k] = want_lo[k];
        hi[k] = want_lo[k] + want_n[k] - 1;
    }
    if (f->mask) include_mask(f->mask, lo, hi);
    if (f->tris) include_tris(f->tris, f->ntris, xf, lo, hi);
    if (f->tris0) include_tris(f->tris0, f->ntris0, xf, lo, hi);
    uint64_t total = 1;
    for (int k = 0; k < 3; ++k) {
        lo[k] -= 2; /* a margin: the contour needs outside voxels around the object */
        hi[k] += 2;
        n[k] = hi[k] - lo[k] + 1;
        total *= (uint64_t)n[k];
    }
    if (total > ((uint64_t)1 << 36))
        return hv_error_set(HV_ERR_LIMIT, "%s: distance field of %lld x %lld x %lld voxels is too large",
                            f->desc, (long long)n[0], (long long)n[1], (long long)n[2]);
    uint8_t *feature = hv_malloc_big((size_t)total, 1); /* every byte set by stamp_mask */
    float *d = hv_malloc_big((size_t)total, sizeof(float));
    hv_status s = HV_OK;
    if (!feature || !d) {
        s = HV_ERR_NOMEM;
        goto done;
    }
    double spacing[3] = {xf->voxel[0], xf->voxel[1], xf->voxel[2]};
    switch (f->kind) {
    case HV_FRF_CONTOUR: {
        /* distance to the nearest voxel outside the mask, less one voxel: the occupied skin
         * reaches about t + L/2 beyond the true surface (t the slab half-thickness), so the
         * depth below the surface is EDT - ~L (accurate to about +-0.4 voxel) */
        /* the depth is EDT - L inside, 0 outside (outside voxels are the EDT's features: 0 - L
         * clamps to 0); the EDT's last pass applies it */
        if ((s = stamp_mask(f->mask, lo, n, feature, 1, 0)) == HV_OK)
            s = hv_edt_less(feature, n, spacing, (float)hv_voxel_scale(xf), d, progress);
        break;
    }
    case HV_FRF_MASK:
        if ((s = stamp_mask(f->mask, lo, n, feature, 0, 1)) == HV_OK) s = hv_edt(feature, n, spacing, d, progress);
        break;
    case HV_FRF_FACETS:
        if ((s = stamp_mask(NULL, lo, n, feature, 0, 0)) == HV_OK &&
            (s = rasterize(f->tris, f->ntris, xf, lo, n, feature, 1)) == HV_OK)
            s = hv_edt(feature, n, spacing, d, progress);
        break;
    case HV_FRF_HARMONIC: {
        uint8_t *label = hv_calloc((size_t)total, 1);
        if (!label) {
            s = HV_ERR_NOMEM;
            break;
        }
        if ((s = stamp_mask(f->mask, lo, n, feature, 0, 1)) == HV_OK &&
            (s = rasterize(f->tris0, f->ntris0, xf, lo, n, label, 2)) == HV_OK &&
            (s = rasterize(f->tris, f->ntris, xf, lo, n, label, 1)) == HV_OK)
            s = hv_harmonic(feature, label, n, spacing, 1e-7, 2000, d, NULL, NULL, progress);
        free(label);
        break;
    }
    default: break;
    }
    if (s != HV_OK) {
        hv_error_prefix(s, "%s: ", f->desc);
        goto done;
    }
    free(f->cache.d);
    f->cache.xf = *xf;
    memcpy(f->cache.lo, lo, sizeof lo);
    memcpy(f->cache.n, n, sizeof n);
    f->cache.d = d;
    d = NULL;
done:
    free(feature);
    free(d);
    return s;
}

hv_status hv_frf_prepare(hv_frf *f, const hv_transform *xf, const int64_t lo[3], const int64_t n[3],
                         const hv_progress *progress)
{
    if (!is_voxel_kind(f->kind)) return HV_OK;
    if (f->mask) {
        hv_transform mxf = hv_volume_get_transform(f->mask);
        if (!hv_transform_same(&mxf, xf))
            return hv_error_set(HV_ERR_INVALID, "%s: the feature was made on another voxel lattice",
                                f->desc);
    }
    pthread_mutex_lock(&f->lock);
    hv_status s = HV_OK;
    const hv_field_cache *c = &f->cache;
    int covered = c->d && hv_transform_same(&c->xf, xf);
    for (int k = 0; k < 3 && covered; ++k)
        covered = lo[k] >= c->lo[k] + 1 && lo[k] + n[k] <= c->lo[k] + c->n[k] - 1;
    if (!covered) s = compute_field(f, xf, lo, n, progress);
    pthread_mutex_unlock(&f->lock);
    return s;
}

/* ---- evaluation --------------------------------------------------------------------------- */

static double analytic(const hv_frf *f, const double p[3])
{
    double v[3] = {p[0] - f->a[0], p[1] - f->a[1], p[2] - f->a[2]};
    switch (f->kind) {
    case HV_FRF_POINT: return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    case HV_FRF_LINE: {
        const double *u = f->b;
        double c[3] = {v[1] * u[2] - v[2] * u[1], v[2] * u[0] - v[0] * u[2], v[0] * u[1] - v[1] * u[0]};
        return sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    }
    case HV_FRF_PLANE: return fabs(v[0] * f->b[0] + v[1] * f->b[1] + v[2] * f->b[2]);
    case HV_FRF_HALFSPACE: return v[0] * f->b[0] + v[1] * f->b[1] + v[2] * f->b[2];
    case HV_FRF_SEGMENT: {
        double ab[3] = {f->b[0] - f->a[0], f->b[1] - f->a[1], f->b[2] - f->a[2]};
        double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
        double t = l2 > 0 ? (v[0] * ab[0] + v[1] * ab[1] + v[2] * ab[2]) / l2 : 0.0;
        t = HV_CLAMP(t, 0.0, 1.0);
        double w[3] = {v[0] - t * ab[0], v[1] - t * ab[1], v[2] - t * ab[2]};
        return sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    }
    default: return 0.0;
    }
}

HV_HOT_CLONES void hv_frf_leaf_distances(const hv_frf *f, const hv_transform *xf, const int32_t o[3], float *d)
{
    if (f->kind == HV_FRF_FIELD) {
        hv_accessor acc;
        hv_accessor_init(&acc, f->mask);
        int64_t l = hv_accessor_leaf(&acc, o[0], o[1], o[2]);
        if (l < 0) memset(d, 0, HV_LEAF_SIZE * sizeof(float));
        else memcpy(d, hv_volume_leaf_float_c(f->mask, 0, (size_t)l), HV_LEAF_SIZE * sizeof(float));
        return;
    }
    if (!is_voxel_kind(f->kind)) {
        double x0 = xf->origin[0] + o[0] * xf->voxel[0], y0 = xf->origin[1] + o[1] * xf->voxel[1],
               z0 = xf->origin[2] + o[2] * xf->voxel[2];
        if (f->kind == HV_FRF_LINE || f->kind == HV_FRF_PLANE || f->kind == HV_FRF_HALFSPACE) {
            /* the hot analytic cases: coordinates relative to the feature in double per row,
             * then float rows the compiler vectorises */
            const double *a = f->a;
            const float u0 = (float)f->b[0], u1 = (float)f->b[1], u2 = (float)f->b[2];
            const float vz = (float)xf->voxel[2];
            for (int x = 0; x < 8; ++x)
                for (int y = 0; y < 8; ++y) {
                    const float px = (float)(x0 + x * xf->voxel[0] - a[0]), py = (float)(y0 + y * xf->voxel[1] - a[1]);
                    const float pz0 = (float)(z0 - a[2]);
                    float *row = d + (x << 6) + (y << 3);
                    if (f->kind == HV_FRF_PLANE) {
                        const float base = px * u0 + py * u1;
#pragma omp simd
                        for (int z = 0; z < 8; ++z) row[z] = fabsf(base + (pz0 + (float)z * vz) * u2);
                    } else if (f->kind == HV_FRF_HALFSPACE) {
                        const float base = px * u0 + py * u1;
#pragma omp simd
                        for (int z = 0; z < 8; ++z) row[z] = base + (pz0 + (float)z * vz) * u2;
                    } else {
                        const float c2 = px * u1 - py * u0;
#pragma omp simd
                        for (int z = 0; z < 8; ++z) {
                            float pz = pz0 + (float)z * vz;
                            float c0 = py * u2 - pz * u1, c1 = pz * u0 - px * u2;
                            row[z] = sqrtf(c0 * c0 + c1 * c1 + c2 * c2);
                        }
                    }
                }
            return;
        }
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
            double p[3] = {x0 + (double)(n >> 6) * xf->voxel[0], y0 + (double)((n >> 3) & 7) * xf->voxel[1],
                           z0 + (double)(n & 7) * xf->voxel[2]};
            d[n] = (float)analytic(f, p);
        }
        return;
    }
    const hv_field_cache *c = &f->cache;
    for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
        int64_t i = o[0] + (int64_t)(n >> 6) - c->lo[0], j = o[1] + (int64_t)((n >> 3) & 7) - c->lo[1],
                k = o[2] + (int64_t)(n & 7) - c->lo[2];
        i = HV_CLAMP(i, 0, c->n[0] - 1);
        j = HV_CLAMP(j, 0, c->n[1] - 1);
        k = HV_CLAMP(k, 0, c->n[2] - 1);
        d[n] = c->d[(i * c->n[1] + j) * c->n[2] + k];
    }
}

/* Trilinear sample of a prepared dense field at a world point. */
static double cache_sample(const hv_field_cache *c, const double p[3])
{
    const hv_transform *xf = &c->xf;
    double idx[3], fr[3];
    int64_t i0[3];
    for (int k = 0; k < 3; ++k) {
        idx[k] = (p[k] - xf->origin[k]) / xf->voxel[k] - (double)c->lo[k];
        idx[k] = HV_CLAMP(idx[k], 0.0, (double)(c->n[k] - 1));
        i0[k] = HV_MIN((int64_t)floor(idx[k]), c->n[k] - 2 < 0 ? 0 : c->n[k] - 2);
        fr[k] = idx[k] - (double)i0[k];
    }
    double acc = 0;
    for (int q = 0; q < 8; ++q) {
        int64_t ii = HV_MIN(i0[0] + (q >> 2), c->n[0] - 1), jj = HV_MIN(i0[1] + ((q >> 1) & 1), c->n[1] - 1),
                kk = HV_MIN(i0[2] + (q & 1), c->n[2] - 1);
        double w = ((q >> 2) ? fr[0] : 1 - fr[0]) * (((q >> 1) & 1) ? fr[1] : 1 - fr[1]) * ((q & 1) ? fr[2] : 1 - fr[2]);
        acc += w * c->d[(ii * c->n[1] + jj) * c->n[2] + kk];
    }
    return acc;
}

double hv_frf_sample(const hv_frf *f, const double p[3])
{
    if (f->kind == HV_FRF_FIELD) {
        hv_accessor acc;
        hv_accessor_init(&acc, f->mask);
        int g = 0;
        float d = 0, cov = 0;
        hv_volume_sample(&acc, &g, 1, p, &d, &cov);
        return (double)d;
    }
    if (!is_voxel_kind(f->kind)) return analytic(f, p);
    return f->cache.d ? cache_sample(&f->cache, p) : 0.0;
}

hv_status hv_frf_distance(hv_frf *f, const hv_volume *lattice, const double p[3], double *d)
{
    if (!is_voxel_kind(f->kind)) {
        *d = hv_frf_sample(f, p);
        return HV_OK;
    }
    hv_transform xf = hv_volume_get_transform(lattice);
    int32_t a[3], b[3];
    int64_t lo[3], n[3];
    if (!hv_volume_index_bbox(lattice, a, b)) a[0] = a[1] = a[2] = b[0] = b[1] = b[2] = 0;
    for (int k = 0; k < 3; ++k) {
        lo[k] = a[k];
        n[k] = (int64_t)b[k] - a[k] + 1;
    }
    hv_status s = hv_frf_prepare(f, &xf, lo, n, NULL);
    if (s != HV_OK) return s;
    *d = cache_sample(&f->cache, p);
    return HV_OK;
}

/* ---- fields recomputed from a stored mask --------------------------------------------------
 * The contour and mask features' fields are pure functions of a bool grid the model already
 * holds (its occupancy, a region): the exact EDT of that grid, which does not depend on the box
 * it is computed over as long as the box holds the mask with a margin (compute_field). So a
 * graded model stores no float grid for them (issue 17: a float distance grid made the
 * contour-graded 512-voxel knot 89 MB against 42 MB graded by an axis, and its writing was most
 * of the time the contour costs over an axis); the loader recomputes it bit for bit, which takes
 * about as long as reading the float grid back did. Fields that are not a function of a grid of
 * the model (from a file, facets, harmonic) keep being stored as float grids. */

/* 1 when the active voxels of mask volume m are exactly the true voxels of bool grid g of v. */
static int mask_is_grid(const hv_volume *m, const hv_volume *v, int g)
{
    hv_transform a = hv_volume_get_transform(m), b = hv_volume_get_transform(v);
    if (!hv_transform_same(&a, &b) || hv_volume_mask_count(v, g) != hv_volume_active_count(m)) return 0;
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    const int32_t *org = hv_volume_leaf_origins(m);
    for (size_t l = 0; l < hv_volume_leaf_count(m); ++l) {
        const uint64_t *mm = hv_volume_leaf_mask(m, l);
        int64_t lv = hv_accessor_leaf(&acc, org[3 * l], org[3 * l + 1], org[3 * l + 2]);
        const uint64_t *vm = lv >= 0 ? hv_volume_leaf_mask(v, (size_t)lv) : NULL;
        const uint64_t *vb = lv >= 0 ? hv_volume_leaf_bool_c(v, g, (size_t)lv) : NULL;
        for (int w = 0; w < HV_LEAF_WORDS; ++w)
            if (mm[w] & ~(vm ? vm[w] & vb[w] : 0)) return 0;
    }
    return 1;
}

const char *hv_frf_derived_grid(const hv_frf *f, const hv_volume *vol)
{
    const hv_volume *m = f->kind == HV_FRF_CONTOUR || f->kind == HV_FRF_MASK ? f->mask
                         : f->kind == HV_FRF_FIELD && f->derived                 ? f->src
                                                                                 : NULL;
    if (!m) return NULL;
    if (!vol) return f->kind == HV_FRF_FIELD ? f->src_grid : NULL;
    /* the usual one first: a contour of the model's own occupancy */
    int first = hv_volume_grid_find(vol, "occupancy");
    if (first >= 0 && hv_volume_grid_type(vol, first) == HV_GRID_BOOL && mask_is_grid(m, vol, first))
        return hv_volume_grid_name(vol, first);
    for (int g = 0; g < hv_volume_grid_count(vol); ++g)
        if (g != first && hv_volume_grid_type(vol, g) == HV_GRID_BOOL && mask_is_grid(m, vol, g))
            return hv_volume_grid_name(vol, g);
    return NULL;
}

/* The field of a contour or mask feature of bool grid `grid` of vol, computed as grading did
 * (over vol's box in whole leaves) and kept as a stored field on vol's active voxels, as the
 * float grid "distance.K" held it. */
static hv_status field_derived(const hv_volume *vol, hv_frf_kind kind, const char *grid, const char *text,
                               hv_frf **out)
{
    *out = NULL;
    hv_frf *src;
    hv_status s = kind == HV_FRF_CONTOUR ? hv_frf_contour(vol, grid, &src) : hv_frf_mask(vol, grid, &src);
    if (s != HV_OK) return s;
    hv_transform xf = hv_volume_get_transform(vol);
    int32_t a[3], b[3];
    int64_t lo[3], n[3];
    if (!hv_volume_index_bbox(vol, a, b)) a[0] = a[1] = a[2] = b[0] = b[1] = b[2] = 0;
    for (int k = 0; k < 3; ++k) {
        lo[k] = a[k] & ~7;
        n[k] = (((int64_t)b[k] | 7) + 1) - lo[k];
    }
    hv_volume *v = NULL;
    if ((s = hv_frf_prepare(src, &xf, lo, n, NULL)) == HV_OK && (s = hv_volume_create(&xf, &v)) == HV_OK &&
        (s = hv_volume_topology_union(v, vol)) == HV_OK && (s = hv_frf_store_field(src, v, "d")) == HV_OK)
        s = new_frf(HV_FRF_FIELD, out);
    if (s != HV_OK) {
        hv_volume_destroy(v);
        hv_frf_release(src);
        return s;
    }
    (*out)->mask = v;
    (*out)->derived = kind;
    (*out)->src = src->mask; /* the mask outlives the dense field */
    snprintf((*out)->src_grid, sizeof (*out)->src_grid, "%s", grid);
    src->mask = NULL;
    hv_frf_release(src);
    snprintf((*out)->desc, sizeof (*out)->desc, "%s", text && *text ? text : grid);
    return HV_OK;
}

hv_status hv_frf_store_field(const hv_frf *f, hv_volume *vol, const char *grid)
{
    int g;
    hv_status s = hv_volume_grid_add(vol, grid, HV_GRID_FLOAT, &g);
    if (s != HV_OK) return s;
    hv_transform xf = hv_volume_get_transform(vol);
    const int32_t *org = hv_volume_leaf_origins(vol);
    for (size_t l = 0; l < hv_volume_leaf_count(vol); ++l) {
        float d[HV_LEAF_SIZE];
        hv_frf_leaf_distances(f, &xf, org + 3 * l, d);
        memcpy(hv_volume_leaf_float(vol, g, l), d, sizeof d);
    }
    return HV_OK;
}

/* Analytic kinds are written with the keys of their option set (hv_frf_option_set: a point
 * "point", an axis "origin" and "direction", ...), so a document reads like the options that
 * make the feature; stored distance fields as kind "field" with their grid. */
static double *param(hv_frf_options *o, const hv_option *opt) { return (double *)((char *)o + opt->offset); }

json_t *hv_frf_to_doc(const hv_frf *f, const char *grid, const char *derived)
{
    json_t *j = json_object();
    if (!j) return NULL;
    const hv_option_set *set = is_analytic_kind(f->kind) ? hv_frf_option_set(f->kind) : NULL;
    hv_frf_kind dk = f->kind == HV_FRF_FIELD ? f->derived : f->kind;
    int failed;
    if (derived && !set && (dk == HV_FRF_CONTOUR || dk == HV_FRF_MASK)) {
        failed = hv_json_set(j, "kind", json_string(hv_frf_kind_name(dk)));
        failed |= hv_json_set(j, "grid", hv_json_text(derived));
    } else if (set) {
        failed = hv_json_set(j, "kind", json_string(set->name));
        hv_frf_options o;
        set->init(&o);
        const double *ab[2] = {f->a, f->b};
        for (int i = 0; i < set->count && i < 2; ++i) {
            memcpy(param(&o, &set->options[i]), ab[i], 3 * sizeof(double));
            failed |= hv_json_set(j, set->options[i].key, hv_json_numbers(param(&o, &set->options[i]), 3));
        }
    } else {
        failed = hv_json_set(j, "kind", json_string("field"));
        failed |= hv_json_set(j, "grid", hv_json_text(grid ? grid : ""));
    }
    failed |= hv_json_set(j, "text", hv_json_text(f->desc));
    if (failed) {
        json_decref(j);
        return NULL;
    }
    return j;
}

hv_status hv_frf_from_doc(const json_t *j, const hv_volume *vol, const char *what, hv_frf **out)
{
    *out = NULL;
    int kind;
    hv_status s = hv_json_get_name(j, "kind", what, hv_frf_kind_enum(), &kind);
    if (s != HV_OK) return s;
    if (kind == HV_FRF_FIELD) {
        const char *grid, *text = NULL;
        if ((s = hv_json_get_string(j, "grid", what, &grid)) != HV_OK) return s;
        if (json_object_get(j, "text") && (s = hv_json_get_string(j, "text", what, &text)) != HV_OK) return s;
        s = hv_frf_field(vol, grid, text, out);
        return s == HV_OK ? s : hv_error_prefix(s == HV_ERR_INVALID ? HV_ERR_BAD_INPUT : s, "%s: ", what);
    }
    if (kind == HV_FRF_CONTOUR || kind == HV_FRF_MASK) {
        const char *grid, *text = NULL;
        if ((s = hv_json_get_string(j, "grid", what, &grid)) != HV_OK) return s;
        if (json_object_get(j, "text") && (s = hv_json_get_string(j, "text", what, &text)) != HV_OK) return s;
        s = field_derived(vol, (hv_frf_kind)kind, grid, text, out);
        return s == HV_OK ? s
                          : hv_error_prefix(s == HV_ERR_INVALID || s == HV_ERR_NOT_FOUND ? HV_ERR_BAD_INPUT : s,
                                            "%s: ", what);
    }
    const hv_option_set *set = is_analytic_kind((hv_frf_kind)kind) ? hv_frf_option_set((hv_frf_kind)kind) : NULL;
    if (!set) return hv_error_set(HV_ERR_BAD_INPUT, "%s: a %s feature is not stored in a model", what, hv_frf_kind_name((hv_frf_kind)kind));
    hv_frf_options o;
    set->init(&o);
    for (int i = 0; i < set->count; ++i)
        if ((s = hv_json_get_numbers(j, set->options[i].key, what, param(&o, &set->options[i]), 3)) != HV_OK) return s;
    s = hv_frf_from_options(&o, NULL, out);
    return s == HV_OK ? s : hv_error_prefix(s == HV_ERR_INVALID ? HV_ERR_BAD_INPUT : s, "%s: ", what);
}
