/* src/material/field_file.c - field features: a scalar field from data (an FEA result, a scan)
 * sampled at the model's voxel centres, where its value plays the role of Wu's distance d. VTK
 * files go through the VTK bridge plugin (src/io/vtk/vtk_bridge.h: vtkProbeFilter), .vdb float
 * grids through the volume store; voxels the field misses are refused or filled from the
 * nearest covered voxel. The result is an ordinary stored field (HV_FRF_FIELD). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "io/vtk/vtk_bridge.h"
#include "material_internal.h"

/* The voxel centres of the true voxels of bool grid 0 of m (n of them, 3 doubles each). */
static hv_status centres(const hv_volume *m, double **xyz, size_t *n)
{
    hv_transform xf = hv_volume_get_transform(m);
    size_t count = 0, nl = hv_volume_leaf_count(m);
    for (size_t l = 0; l < nl; ++l) {
        const uint64_t *mask = hv_volume_leaf_mask(m, l);
        for (int w = 0; w < 8; ++w) count += (size_t)__builtin_popcountll(mask[w]);
    }
    double *p = hv_malloc_array(count ? count : 1, 3 * sizeof(double));
    if (!p) return HV_ERR_NOMEM;
    const int32_t *org = hv_volume_leaf_origins(m);
    size_t k = 0;
    for (size_t l = 0; l < nl; ++l) {
        const uint64_t *mask = hv_volume_leaf_mask(m, l);
        for (unsigned q = 0; q < HV_LEAF_SIZE; ++q) {
            if (!HV_BIT_GET(mask, q)) continue;
            int32_t idx[3] = {org[3 * l] + (int32_t)(q >> 6), org[3 * l + 1] + (int32_t)((q >> 3) & 7),
                              org[3 * l + 2] + (int32_t)(q & 7)};
            for (int a = 0; a < 3; ++a) p[3 * k + (size_t)a] = xf.origin[a] + idx[a] * xf.voxel[a];
            ++k;
        }
    }
    *xyz = p;
    *n = count;
    return HV_OK;
}

static const char *ext_of(const char *path)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    return dot && (!slash || dot > slash) ? dot : "";
}

/* A .vdb float grid sampled trilinearly over its active voxels. */
static hv_status probe_vdb(const char *path, const char *grid, size_t n, const double *xyz, float *out,
                           uint8_t *valid, double range[2])
{
    hv_volume *v;
    hv_status s = hv_volume_load(path, &v);
    if (s != HV_OK) return s;
    int g = hv_volume_grid_need(v, grid, HV_GRID_FLOAT);
    if (g < 0) {
        hv_volume_destroy(v);
        return hv_error_prefix(HV_ERR_BAD_INPUT, "%s: ", path);
    }
    range[0] = INFINITY;
    range[1] = -INFINITY;
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        const uint64_t *mask = hv_volume_leaf_mask(v, l);
        const float *d = hv_volume_leaf_float_c(v, g, l);
        for (unsigned q = 0; q < HV_LEAF_SIZE; ++q)
            if (HV_BIT_GET(mask, q)) {
                range[0] = fmin(range[0], d[q]);
                range[1] = fmax(range[1], d[q]);
            }
    }
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    for (size_t i = 0; i < n; ++i) {
        float d = 0, cov = 0;
        hv_volume_sample(&acc, &g, 1, xyz + 3 * i, &d, &cov);
        valid[i] = cov > 0 && isfinite(d);
        out[i] = valid[i] ? d : 0.0f;
    }
    hv_volume_destroy(v);
    return HV_OK;
}

static hv_status probe_vtk(const char *path, const char *array, size_t n, const double *xyz, float *out,
                           uint8_t *valid, double range[2])
{
    const hv_vtk_api *api;
    hv_status s = hv_vtk_bridge(&api);
    if (s != HV_OK) return s;
    hv_vtk_probe_info info;
    memset(&info, 0, sizeof info);
    hv_input_note(path);
    int rc = api->probe(path, array, (int64_t)n, xyz, out, valid, &info);
    if (rc != HV_OK) return hv_error_set((hv_status)rc, "%s", api->last_error());
    range[0] = info.range[0];
    range[1] = info.range[1];
    return HV_OK;
}

/* Fill the voxels not covered from the nearest covered voxel (Euclidean, anisotropic spacing):
 * each voxel of the model's index box keeps its nearest source found so far, and a breadth-first
 * wave over 26-neighbours passes sources on while they are nearer (a voxel is queued again when
 * its source improves), as in vector distance transforms (Danielsson 1980); ties go to the
 * source reached first, deterministic. */
static hv_status fill_nearest(const hv_volume *m, float *val, const uint8_t *valid, size_t n)
{
    int32_t lo[3], hi[3];
    if (!hv_volume_index_bbox(m, lo, hi)) return HV_OK;
    hv_transform xf = hv_volume_get_transform(m);
    int64_t dim[3] = {hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1};
    size_t total = (size_t)(dim[0] * dim[1] * dim[2]), qcap = total, qh = 0, qt = 0;
    int64_t *src = hv_malloc_array(total, sizeof(int64_t));
    int64_t *queue = hv_malloc_array(qcap, sizeof(int64_t));
    int64_t *at = hv_malloc_array(n ? n : 1, sizeof(int64_t));
    float *bv = hv_malloc_array(total, sizeof(float));
    hv_status s = HV_OK;
    if (!src || !queue || !at || !bv) {
        s = HV_ERR_NOMEM;
        goto done;
    }
    for (size_t v = 0; v < total; ++v) src[v] = -1;
    const int32_t *org = hv_volume_leaf_origins(m);
    size_t k = 0;
    for (size_t l = 0; l < hv_volume_leaf_count(m); ++l) {
        const uint64_t *mask = hv_volume_leaf_mask(m, l);
        for (unsigned q = 0; q < HV_LEAF_SIZE; ++q) {
            if (!HV_BIT_GET(mask, q)) continue;
            int64_t i = org[3 * l] + (int64_t)(q >> 6) - lo[0], j = org[3 * l + 1] + (int64_t)((q >> 3) & 7) - lo[1],
                    kk = org[3 * l + 2] + (int64_t)(q & 7) - lo[2];
            at[k] = (i * dim[1] + j) * dim[2] + kk;
            if (valid[k]) {
                src[at[k]] = at[k];
                bv[at[k]] = val[k];
            }
            ++k;
        }
    }
    for (size_t v = 0; v < total; ++v)
        if (src[v] == (int64_t)v) queue[qt++] = (int64_t)v;
#define COORDS(v, c) \
    do { \
        c[0] = (v) / (dim[1] * dim[2]); \
        c[1] = ((v) / dim[2]) % dim[1]; \
        c[2] = (v) % dim[2]; \
    } while (0)
    while (qh != qt) {
        int64_t v = queue[qh];
        qh = (qh + 1) % qcap;
        int64_t c[3], sc[3];
        COORDS(v, c);
        COORDS(src[v], sc);
        for (int di = -1; di <= 1; ++di)
            for (int dj = -1; dj <= 1; ++dj)
                for (int dk = -1; dk <= 1; ++dk) {
                    int64_t a[3] = {c[0] + di, c[1] + dj, c[2] + dk};
                    if (a[0] < 0 || a[1] < 0 || a[2] < 0 || a[0] >= dim[0] || a[1] >= dim[1] || a[2] >= dim[2]) continue;
                    int64_t w = (a[0] * dim[1] + a[1]) * dim[2] + a[2];
                    double dn = 0, dold = 0;
                    int64_t oc[3];
                    if (src[w] >= 0) COORDS(src[w], oc);
                    for (int e = 0; e < 3; ++e) {
                        double u = (double)(a[e] - sc[e]) * xf.voxel[e];
                        dn += u * u;
                        if (src[w] >= 0) {
                            double o = (double)(a[e] - oc[e]) * xf.voxel[e];
                            dold += o * o;
                        }
                    }
                    if (src[w] >= 0 && !(dn < dold - 1e-12)) continue;
                    src[w] = src[v];
                    bv[w] = bv[src[v]];
                    if ((qt + 1) % qcap == qh) { /* full: grow the ring */
                        int64_t *nq = hv_malloc_array(2 * qcap, sizeof(int64_t));
                        if (!nq) {
                            s = HV_ERR_NOMEM;
                            goto done;
                        }
                        size_t len = 0;
                        for (size_t r = qh; r != qt; r = (r + 1) % qcap) nq[len++] = queue[r];
                        free(queue);
                        queue = nq;
                        qcap *= 2;
                        qh = 0;
                        qt = len;
                    }
                    queue[qt] = w;
                    qt = (qt + 1) % qcap;
                }
    }
#undef COORDS
    for (size_t q = 0; q < n; ++q)
        if (!valid[q]) val[q] = bv[at[q]];
done:
    free(src);
    free(queue);
    free(at);
    free(bv);
    return s;
}

/* Samples a field at n points: val[i] and valid[i] (0: the point lies outside the field), and
 * the field's own range. */
typedef hv_status (*probe_fn)(void *ctx, size_t n, const double *xyz, float *val, uint8_t *valid, double range[2]);

typedef struct file_probe {
    const char *path, *array;
    int vdb;
} file_probe;

static hv_status probe_file(void *ctx, size_t n, const double *xyz, float *val, uint8_t *valid, double range[2])
{
    const file_probe *f = ctx;
    return f->vdb ? probe_vdb(f->path, f->array, n, xyz, val, valid, range)
                  : probe_vtk(f->path, f->array, n, xyz, val, valid, range);
}

/* A field feature on bool grid `grid` of vol from a probe: the voxel centres sampled, the voxels
 * not covered refused or filled, the values stored as the feature's field. `label` names the
 * field in messages ("s.vti: sigma"), `desc` is the feature's description. */
static hv_status field_feature(const hv_volume *vol, const char *grid, const char *label, const char *desc,
                               probe_fn probe, void *ctx, hv_field_outside outside, hv_frf **out)
{
    grid = grid ? grid : "occupancy";
    int g = hv_volume_grid_need(vol, grid, HV_GRID_BOOL);
    if (g < 0) return hv_error_prefix(HV_ERR_NOT_FOUND, "the model has ");
    hv_transform xf = hv_volume_get_transform(vol);
    hv_volume *m = NULL;
    double *xyz = NULL;
    float *val = NULL;
    uint8_t *valid = NULL;
    size_t n = 0;
    hv_status s = hv_volume_create(&xf, &m);
    if (s == HV_OK) s = hv_volume_grid_copy(m, "mask", vol, g);
    if (s == HV_OK) s = hv_volume_topology_restrict(m, 0);
    if (s == HV_OK) s = centres(m, &xyz, &n);
    if (s == HV_OK && n == 0) s = hv_error_set(HV_ERR_INVALID, "bool grid '%s' is empty", grid);
    if (s == HV_OK) {
        val = hv_malloc_array(n, sizeof(float));
        valid = hv_malloc(n);
        if (!val || !valid) s = HV_ERR_NOMEM;
    }
    hv_field_report rep;
    memset(&rep, 0, sizeof rep);
    double range[2] = {0, 0};
    if (s == HV_OK) s = probe(ctx, n, xyz, val, valid, range);
    uint64_t covered = 0;
    for (size_t i = 0; s == HV_OK && i < n; ++i) covered += valid[i];
    if (s == HV_OK && covered == 0)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s covers none of the model's %zu voxels (no overlap: are they in the "
                         "same coordinates?)", label, n);
    if (s == HV_OK && covered < n && outside == HV_FIELD_REFUSE)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s covers %llu of the model's %zu voxels; %llu lie outside it (the rule "
                         "'nearest' gives them the nearest covered value)", label, (unsigned long long)covered, n,
                         (unsigned long long)(n - covered));
    if (s == HV_OK && covered < n) s = fill_nearest(m, val, valid, n);
    /* the field as a float grid on the model's voxels, then an ordinary stored-field feature */
    int gd = -1;
    if (s == HV_OK) s = hv_volume_grid_add(m, "d", HV_GRID_FLOAT, &gd);
    if (s == HV_OK) {
        rep.lo = INFINITY;
        rep.hi = -INFINITY;
        size_t k = 0;
        for (size_t l = 0; l < hv_volume_leaf_count(m); ++l) {
            const uint64_t *mask = hv_volume_leaf_mask(m, l);
            float *d = hv_volume_leaf_float(m, gd, l);
            for (unsigned q = 0; q < HV_LEAF_SIZE; ++q) {
                if (!HV_BIT_GET(mask, q)) continue;
                d[q] = val[k];
                rep.lo = fmin(rep.lo, val[k]);
                rep.hi = fmax(rep.hi, val[k]);
                ++k;
            }
        }
        s = hv_frf_field(m, "d", desc, out);
    }
    if (s == HV_OK) {
        rep.file_lo = range[0];
        rep.file_hi = range[1];
        rep.voxels = n;
        rep.filled = n - covered;
        (*out)->has_report = 1;
        (*out)->report = rep;
    }
    free(xyz);
    free(val);
    free(valid);
    hv_volume_destroy(m);
    return s;
}

hv_status hv_frf_field_file(const hv_volume *vol, const char *grid, const char *path, const char *array,
                            hv_field_outside outside, hv_frf **out)
{
    *out = NULL;
    if (!path || !*path || !array || !*array)
        return hv_error_set(HV_ERR_INVALID, "a field feature needs a file and an array");
    const char *ext = ext_of(path);
    int vdb = !strcasecmp(ext, ".vdb");
    if (!vdb && strcasecmp(ext, ".vti") != 0 && strcasecmp(ext, ".vtu") != 0)
        return hv_error_set(HV_ERR_UNSUPPORTED, "%s: a field is read from .vti, .vtu or .vdb, not '%s'", path, ext);
    file_probe f = {path, array, vdb};
    char label[512], desc[256];
    snprintf(label, sizeof label, "%s: %s", path, array);
    snprintf(desc, sizeof desc, "field(%s:%s)", path, array);
    return field_feature(vol, grid, label, desc, probe_file, &f, outside, out);
}

/* A dense grid of point samples, trilinear inside its box (as VTK interpolates image data: the
 * cell holding the point, its eight corners weighted in vtkVoxel's order). */
static double grid_value_d(const hv_field_grid *g, int64_t i, int64_t j, int64_t k)
{
    size_t at = (size_t)((i * g->dims[1] + j) * g->dims[2] + k);
    return g->double_values ? ((const double *)g->values)[at] : (double)((const float *)g->values)[at];
}

static hv_status probe_grid(void *ctx, size_t n, const double *xyz, float *val, uint8_t *valid, double range[2])
{
    const hv_field_grid *g = ctx;
    for (size_t i = 0; i < n; ++i) {
        int64_t c[3];
        double t[3];
        int in = 1;
        for (int a = 0; a < 3 && in; ++a) {
            double u = (xyz[3 * i + (size_t)a] - g->origin[a]) / g->spacing[a];
            double last = (double)(g->dims[a] - 1);
            if (!(u >= 0 && u <= last)) {
                in = 0;
                break;
            }
            c[a] = (int64_t)floor(u);
            if (c[a] >= g->dims[a] - 1) c[a] = g->dims[a] > 1 ? g->dims[a] - 2 : 0; /* the far face */
            t[a] = g->dims[a] > 1 ? u - (double)c[a] : 0.0;
        }
        valid[i] = (uint8_t)in;
        val[i] = 0.0f;
        if (!in) continue;
        int64_t d[3];
        for (int a = 0; a < 3; ++a) d[a] = g->dims[a] > 1 ? 1 : 0;
        double r = t[0], s = t[1], q = t[2], rm = 1 - r, sm = 1 - s, qm = 1 - q;
        double w[8] = {rm * sm * qm, r * sm * qm, rm * s * qm, r * s * qm, rm * sm * q, r * sm * q, rm * s * q, r * s * q};
        double v = 0;
        for (int p = 0; p < 8; ++p) {
            int64_t ii = c[0] + ((p & 1) ? d[0] : 0), jj = c[1] + ((p & 2) ? d[1] : 0), kk = c[2] + ((p & 4) ? d[2] : 0);
            v += w[p] * grid_value_d(g, ii, jj, kk);
        }
        val[i] = (float)v;
    }
    range[0] = INFINITY;
    range[1] = -INFINITY;
    size_t total = (size_t)(g->dims[0] * g->dims[1] * g->dims[2]);
    for (size_t p = 0; p < total; ++p) {
        double v = g->double_values ? ((const double *)g->values)[p] : (double)((const float *)g->values)[p];
        range[0] = fmin(range[0], v);
        range[1] = fmax(range[1], v);
    }
    return HV_OK;
}

hv_status hv_frf_field_grid(const hv_volume *vol, const char *grid, const hv_field_grid *g, const char *name,
                            hv_field_outside outside, hv_frf **out)
{
    *out = NULL;
    name = name && *name ? name : "array";
    if (!g || !g->values) return hv_error_set(HV_ERR_INVALID, "field %s: no values", name);
    uint64_t total = 1;
    for (int a = 0; a < 3; ++a) {
        if (g->dims[a] < 1 || g->dims[a] > (1 << 24))
            return hv_error_set(HV_ERR_INVALID, "field %s: %lld samples along axis %d (1 to %d)", name,
                                (long long)g->dims[a], a, 1 << 24);
        if (!(g->spacing[a] > 0) || !isfinite(g->spacing[a]) || !isfinite(g->origin[a]))
            return hv_error_set(HV_ERR_INVALID, "field %s: spacing must be finite and > 0 and the origin finite "
                                "(axis %d: spacing %g, origin %g)", name, a, g->spacing[a], g->origin[a]);
        total *= (uint64_t)g->dims[a];
        if (total > ((uint64_t)1 << 40)) return hv_error_set(HV_ERR_LIMIT, "field %s: too many samples", name);
    }
    for (int64_t i = 0; i < g->dims[0]; ++i)
        for (int64_t j = 0; j < g->dims[1]; ++j)
            for (int64_t k = 0; k < g->dims[2]; ++k)
                if (!isfinite(grid_value_d(g, i, j, k)))
                    return hv_error_set(HV_ERR_INVALID, "field %s: the value at [%lld, %lld, %lld] is %g (values must be "
                                        "finite)", name, (long long)i, (long long)j, (long long)k, grid_value_d(g, i, j, k));
    char desc[256];
    snprintf(desc, sizeof desc, "field(%s)", name);
    return field_feature(vol, grid, name, desc, probe_grid, (void *)(uintptr_t)g, outside, out);
}

int hv_frf_field_report(const hv_frf *f, hv_field_report *r)
{
    if (!f->has_report) return 0;
    *r = f->report;
    return 1;
}
