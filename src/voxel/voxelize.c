/* src/voxel/voxelize.c - mesh voxelization after Wu 2.1 and Huang, Yagel, Filippov, Kurzion
 * (1998): each triangle marks the voxels whose centres lie in its face slab |n.c + D| <= t
 * bounded by the three edge planes, or within Rc of an edge (cylinder) or vertex (sphere):
 *   adjacency 6:  t = (L/2) max(|A|,|B|,|C|),  Rc = L/2         (no 6-connected tunnel)
 *   adjacency 26: t = (L/2) (|A|+|B|+|C|),     Rc = (sqrt 3/2) L (no 26-connected tunnel)
 * Work happens in index space (voxel centres at integers, L = 1), which also handles
 * anisotropic voxels: separation is a property of the lattice. Only each triangle's voxel
 * bounding box is visited, column by column along the normal's dominant axis. */
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "mesh/mesh_internal.h"
#include "bitgrid.h"
#include "hovox/geometry.h"
#include "hovox/voxelize.h"
#include "voxel_internal.h"
#include "volumes/schema.h"

#define PAD 8 /* empty voxels around the mesh box, so the grid border is outside */

/* ---- bit grids ------------------------------------------------------------------------- */

uint64_t hv_bitgrid_bytes(const int64_t n[3])
{
    return (uint64_t)n[0] * (uint64_t)n[1] * (uint64_t)((n[2] + 63) / 64) * 8u;
}

hv_status hv_bitgrid_init(hv_bitgrid *g, const int64_t n[3], const int64_t lo[3])
{
    memset(g, 0, sizeof *g);
    memcpy(g->n, n, sizeof g->n);
    memcpy(g->lo, lo, sizeof g->lo);
    g->words = (n[2] + 63) / 64;
    g->bits = hv_calloc((size_t)(n[0] * n[1] * g->words), sizeof(uint64_t));
    return g->bits ? HV_OK : HV_ERR_NOMEM;
}

void hv_bitgrid_free(hv_bitgrid *g)
{
    free(g->bits);
    g->bits = NULL;
}

/* ---- planning ---------------------------------------------------------------------------- */

static int64_t round_up8(int64_t x) { return (x + 7) & ~(int64_t)7; }

/* The dense working grid: the plan's voxels plus PAD empty voxels around them, aligned to 8 so
 * its 8^3 blocks are the volume's leaves. */
static void grid_box(const hv_voxel_plan *p, int64_t lo[3], int64_t n[3])
{
    for (int a = 0; a < 3; ++a) {
        int64_t l = p->first[a] - PAD;
        lo[a] = l >= 0 ? l & ~(int64_t)7 : -((-l + 7) & ~(int64_t)7);
        n[a] = round_up8(p->first[a] + p->dims[a] + PAD - lo[a]);
    }
}

/* Area and signed volume of a body's facets (no welding: for planning). */
static void body_measure(const hv_mesh *m, const hv_mesh_body *b, double *area, double *vol)
{
    const float *xyz = hv_mesh_vertices(m);
    const uint32_t *tri = hv_mesh_facets(m);
    double a = 0, v = 0;
    for (size_t f = b->first_facet; f < b->first_facet + b->facet_count; ++f) {
        const float *p = xyz + 3 * (size_t)tri[3 * f], *q = xyz + 3 * (size_t)tri[3 * f + 1],
                    *r = xyz + 3 * (size_t)tri[3 * f + 2];
        double u[3], w[3], c[3];
        for (int k = 0; k < 3; ++k) {
            u[k] = (double)q[k] - p[k];
            w[k] = (double)r[k] - p[k];
        }
        c[0] = u[1] * w[2] - u[2] * w[1];
        c[1] = u[2] * w[0] - u[0] * w[2];
        c[2] = u[0] * w[1] - u[1] * w[0];
        a += 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        v += (p[0] * ((double)q[1] * r[2] - (double)q[2] * r[1]) - p[1] * ((double)q[0] * r[2] - (double)q[2] * r[0]) +
              p[2] * ((double)q[0] * r[1] - (double)q[1] * r[0])) / 6.0;
    }
    *area = a;
    *vol = v;
}

hv_status hv_voxelize_plan(const hv_mesh *mesh, const hv_voxelize_options *opt, hv_voxel_plan *p)
{
    memset(p, 0, sizeof *p);
    const hv_mesh_report *r = hv_mesh_get_report(mesh);
    const char *name = *hv_mesh_name(mesh) ? hv_mesh_name(mesh) : "mesh";
    hv_status st = hv_voxelize_options_check(opt);
    if (st != HV_OK) return st;
    int64_t dims0 = opt->dims[0] || opt->dims[1] || opt->dims[2] ? opt->dims[0] : HV_VOXELIZE_DEFAULT_DIMS;
    double ext[3], ctr[3];
    for (int a = 0; a < 3; ++a) {
        ext[a] = r->bbox_max[a] - r->bbox_min[a];
        ctr[a] = 0.5 * (r->bbox_max[a] + r->bbox_min[a]);
    }
    double longest = HV_MAX(ext[0], HV_MAX(ext[1], ext[2]));
    /* a mesh that is one point has nothing to voxelize, whatever the resolution (issue 32 item 12:
     * --voxel-size and --like took it) */
    if (!(longest > 0)) return hv_error_set(HV_ERR_INVALID, "%s: the mesh has no extent", name);
    int snapped = 0; /* origin set below from a lattice phase instead of centring */
    double phase[3] = {0, 0, 0};
    if (opt->lattice) {
        for (int a = 0; a < 3; ++a) {
            double v = opt->lattice->voxel[a];
            if (!(v > 0) || !isfinite(v) || !isfinite(opt->lattice->origin[a]))
                return hv_error_set(HV_ERR_INVALID, "the target lattice has voxel size %g on axis %c", v, "xyz"[a]);
            p->xf.voxel[a] = v;
            phase[a] = opt->lattice->origin[a];
        }
        snapped = 1;
    } else if (opt->voxel_size[0] != 0 || opt->voxel_size[1] != 0 || opt->voxel_size[2] != 0) {
        for (int a = 0; a < 3; ++a) {
            double v = opt->voxel_size[a];
            if (!(v > 0) || !isfinite(v))
                return hv_error_set(HV_ERR_INVALID, "voxel size on axis %c must be > 0 (got %g)",
                                    "xyz"[a], v);
            double d = ceil(ext[a] / v - 1e-9);
            if (d > 2147483647.0)
                return hv_error_set(HV_ERR_LIMIT,
                                    "%s: voxel size %g gives %.0f voxels on axis %c (limit 2^31)",
                                    name, v, d, "xyz"[a]);
            (void)d;
            p->xf.voxel[a] = v;
            phase[a] = 0.5 * v;
        }
        snapped = 1;
    } else if (dims0 > 0 && opt->dims[1] == 0 && opt->dims[2] == 0) {
        if (!(longest > 0))
            return hv_error_set(HV_ERR_INVALID, "%s: the mesh has no extent", name);
        double v = longest / (double)dims0;
        for (int a = 0; a < 3; ++a) {
            p->xf.voxel[a] = v;
            p->dims[a] = HV_MAX((int64_t)ceil(ext[a] / v - 1e-9), 1);
        }
    } else if (opt->dims[0] > 0 && opt->dims[1] > 0 && opt->dims[2] > 0) {
        for (int a = 0; a < 3; ++a) {
            if (!(ext[a] > 0))
                return hv_error_option(HV_ERR_INVALID,
                                    "%s: the mesh is flat along %c, so dims on that axis cannot "
                                    "set a voxel size; give {voxel_size}",
                                    name, "xyz"[a]);
            p->dims[a] = opt->dims[a];
            p->xf.voxel[a] = ext[a] / (double)opt->dims[a];
        }
    } else {
        return hv_error_set(HV_ERR_INVALID,
                            "give a voxel size, dims along the longest axis, or dims on all "
                            "three axes (got %lld,%lld,%lld)",
                            (long long)opt->dims[0], (long long)opt->dims[1],
                            (long long)opt->dims[2]);
    }
    if (snapped) {
        /* the lattice's voxels (centres at phase + n v) that cover the box */
        for (int a = 0; a < 3; ++a) {
            double v = p->xf.voxel[a];
            /* the voxels whose cells [c - v/2, c + v/2) meet the box */
            double n0 = floor((r->bbox_min[a] - phase[a]) / v + 0.5);
            double n1 = HV_MAX(n0, ceil((r->bbox_max[a] - phase[a]) / v - 0.5));
            if (n1 - n0 + 1 > 2147483647.0 || fabs(n0) > 1e15)
                return hv_error_set(HV_ERR_LIMIT, "%s: voxel size %g gives %.0f voxels on axis %c (limit 2^31)",
                                    name, v, n1 - n0 + 1, "xyz"[a]);
            p->dims[a] = (int64_t)(n1 - n0) + 1;
            p->first[a] = (int64_t)n0;
            /* index 0 is the lattice's point nearest the phase origin, not the box corner */
            p->xf.origin[a] = phase[a];
        }
    } else {
        /* centre the grid on the mesh box: voxel i covers [c + (i - d/2) v, c + (i + 1 - d/2) v] */
        for (int a = 0; a < 3; ++a)
            p->xf.origin[a] = ctr[a] - 0.5 * (double)(p->dims[a] - 1) * p->xf.voxel[a];
    }

    p->fill = opt->fill == HV_FILL_AUTO ? hv_fill_auto(r) : opt->fill;

    /* memory: working bit grids (surface, outside or three parity grids), flood queue or
     * crossing lists, and the volume's leaves (estimated from the mesh volume and area) */
    int64_t n[3], lo[3];
    grid_box(p, lo, n);
    uint64_t grid = hv_bitgrid_bytes(n);
    uint64_t rows = (uint64_t)n[0] * (uint64_t)n[1];
    uint64_t work = 2 * grid + rows * 5u;
    if (p->fill == HV_FILL_VOTE) {
        double vv = p->xf.voxel[0] * p->xf.voxel[1] * p->xf.voxel[2];
        double cross = r->area / cbrt(vv) / cbrt(vv) * 3.0; /* crossings of one axis, generous */
        work = 5 * grid + (uint64_t)(cross * 12.0) + rows * 8u;
    }
    double cell = 8.0 * cbrt(p->xf.voxel[0] * p->xf.voxel[1] * p->xf.voxel[2]);
    double blocks = fabs(r->volume) / (cell * cell * cell) + 3.0 * r->area / (cell * cell);
    double all_blocks = (double)(n[0] / 8) * (double)(n[1] / 8) * (double)(n[2] / 8);
    uint64_t leaves = (uint64_t)HV_MIN(blocks, all_blocks) + 1;
    p->memory_bytes = work + hv_volume_memory_estimate(leaves, 0, 2) + (uint64_t)mesh_bytes(mesh);
    size_t nbodies = hv_mesh_body_count(mesh);
    if (nbodies > 1) {
        /* an assembly: AUTO is decided per body when it is voxelized; one body's working set at a
         * time (at most the whole grid's: surface, occupancy, centres and the vote's three parity
         * grids), the union's five grids, each body's two leaf-block lists kept until the second
         * pass (first-pass voxels and skin candidates, each at most the body's leaves, from its own
         * area and volume) and one bool grid per region */
        p->fill = opt->fill;
        uint64_t region_leaves = 0;
        size_t biggest = 0;
        for (size_t b = 0; b < nbodies; ++b) {
            const hv_mesh_body *body = hv_mesh_body_at(mesh, b);
            size_t len = strlen(body->name);
            if (len > HV_REGION_NAME_MAX)
                return hv_error_set(HV_ERR_BAD_INPUT, "%s: body %zu ('%.40s...'): its name is %zu bytes long, more "
                                                      "than the %d a region's grid name allows",
                                    name, b + 1, body->name, len, HV_REGION_NAME_MAX);
            double area, vol;
            body_measure(mesh, body, &area, &vol);
            double bb = fabs(vol) / (cell * cell * cell) + 3.0 * area / (cell * cell);
            region_leaves += (uint64_t)HV_MIN(bb, all_blocks) + 1;
            biggest = HV_MAX(biggest, body->facet_count);
        }
        double vv = p->xf.voxel[0] * p->xf.voxel[1] * p->xf.voxel[2];
        double cross = r->area / cbrt(vv) / cbrt(vv) * 3.0;
        uint64_t body_work = 6 * grid + (uint64_t)(cross * 12.0) + rows * 8u;
        p->memory_bytes = body_work + 5 * grid + 2 * region_leaves * (8 * sizeof(uint64_t) + 3 * sizeof(int32_t)) +
                          hv_volume_memory_estimate(leaves, 0, 2 + (int)HV_MIN(nbodies, (size_t)INT32_MAX - 2)) +
                          (uint64_t)mesh_bytes(mesh) + (uint64_t)biggest * 100u;
    }

    uint64_t budget = hv_memory_budget(opt->max_memory);
    if (budget && p->memory_bytes > budget) {
        char need[32], have[32];
        return hv_error_option(HV_ERR_LIMIT,
                            "%s: voxelizing at %lld x %lld x %lld needs about %s, more than the "
                            "limit of %s ({max_memory})",
                            name, (long long)p->dims[0], (long long)p->dims[1], (long long)p->dims[2],
                            hv_size_text(need, sizeof need, (double)p->memory_bytes),
                            hv_size_text(have, sizeof have, (double)budget));
    }
    return HV_OK;
}

/* ---- surface ------------------------------------------------------------------------------ */

typedef struct surf_ctx {
    const hv_mesh *mesh;
    const double *P; /* vertices in grid coordinates (voxel centres at integers) */
    hv_bitgrid *S;
    int adj26;
} surf_ctx;

static double dist2_segment(const double *a, const double *b, const double *c)
{
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    double s = l2 > 0 ? (ab[0] * ac[0] + ab[1] * ac[1] + ab[2] * ac[2]) / l2 : 0.0;
    s = HV_CLAMP(s, 0.0, 1.0);
    double d[3] = {ac[0] - s * ab[0], ac[1] - s * ab[1], ac[2] - s * ab[2]};
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

void hv_voxel_mark_triangle(const double *p[3], int adj26, hv_bitgrid *S)
{
    double e1[3], e2[3], n[3];
    for (int a = 0; a < 3; ++a) {
        e1[a] = p[1][a] - p[0][a];
        e2[a] = p[2][a] - p[0][a];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    /* Huang's inequalities are closed: a face exactly halfway between two voxel layers must
     * mark both. Evaluate them with a tolerance far below a voxel so rounding never drops a
     * boundary case (which would open a tunnel along the face). */
    const double eps = 1e-7;
    double rc = adj26 ? sqrt(3.0) / 2 : 0.5, rc2 = (rc + eps) * (rc + eps);
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = ceil(HV_MIN(p[0][a], HV_MIN(p[1][a], p[2][a])) - rc - eps);
        hi[a] = floor(HV_MAX(p[0][a], HV_MAX(p[1][a], p[2][a])) + rc + eps);
        lo[a] = HV_MAX(lo[a], 0.0);
        hi[a] = HV_MIN(hi[a], (double)(S->n[a] - 1));
    }
    int degenerate = !(len > 1e-300);
    double m[3][3] = {{0}}, mo[3] = {0}, ml[3] = {0}, D = 0, t = 0;
    int w = 2, u = 0, v = 1;
    if (!degenerate) {
        for (int a = 0; a < 3; ++a) n[a] /= len;
        D = -(n[0] * p[0][0] + n[1] * p[0][1] + n[2] * p[0][2]);
        double an[3] = {fabs(n[0]), fabs(n[1]), fabs(n[2])};
        t = adj26 ? 0.5 * (an[0] + an[1] + an[2]) : 0.5 * HV_MAX(an[0], HV_MAX(an[1], an[2]));
        /* edge planes: through the edge, containing the normal, facing the third vertex */
        for (int k = 0; k < 3; ++k) {
            const double *a = p[k], *b = p[(k + 1) % 3], *o = p[(k + 2) % 3];
            double eb[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            m[k][0] = n[1] * eb[2] - n[2] * eb[1];
            m[k][1] = n[2] * eb[0] - n[0] * eb[2];
            m[k][2] = n[0] * eb[1] - n[1] * eb[0];
            mo[k] = -(m[k][0] * a[0] + m[k][1] * a[1] + m[k][2] * a[2]);
            if (m[k][0] * o[0] + m[k][1] * o[1] + m[k][2] * o[2] + mo[k] < 0) {
                for (int q = 0; q < 3; ++q) m[k][q] = -m[k][q];
                mo[k] = -mo[k];
            }
            ml[k] = sqrt(m[k][0] * m[k][0] + m[k][1] * m[k][1] + m[k][2] * m[k][2]);
        }
        w = an[0] >= an[1] && an[0] >= an[2] ? 0 : an[1] >= an[2] ? 1 : 2;
        u = (w + 1) % 3;
        v = (w + 2) % 3;
    }
    for (double iu = lo[u]; iu <= hi[u]; iu += 1.0)
        for (double iv = lo[v]; iv <= hi[v]; iv += 1.0) {
            double w0 = lo[w], w1 = hi[w];
            if (!degenerate) {
                /* |n.c + D| <= rc bounds w to a short interval: nothing further can be within
                 * rc of the triangle (distance to the plane <= distance to the triangle) */
                double base = -(D + n[u] * iu + n[v] * iv);
                double a1 = (base - rc - eps) / n[w], a2 = (base + rc + eps) / n[w];
                w0 = HV_MAX(w0, ceil(HV_MIN(a1, a2)));
                w1 = HV_MIN(w1, floor(HV_MAX(a1, a2)));
            }
            for (double iw = w0; iw <= w1; iw += 1.0) {
                double q[3];
                q[u] = iu;
                q[v] = iv;
                q[w] = iw;
                int hit = 0;
                if (!degenerate) {
                    double d = n[0] * q[0] + n[1] * q[1] + n[2] * q[2] + D;
                    if (fabs(d) <= t + eps &&
                        m[0][0] * q[0] + m[0][1] * q[1] + m[0][2] * q[2] + mo[0] >= -eps * ml[0] &&
                        m[1][0] * q[0] + m[1][1] * q[1] + m[1][2] * q[2] + mo[1] >= -eps * ml[1] &&
                        m[2][0] * q[0] + m[2][1] * q[1] + m[2][2] * q[2] + mo[2] >= -eps * ml[2])
                        hit = 1;
                }
                if (!hit)
                    for (int k = 0; k < 3 && !hit; ++k)
                        if (dist2_segment(p[k], p[(k + 1) % 3], q) <= rc2) hit = 1;
                if (hit) hv_bitgrid_set_atomic(S, (int64_t)q[0], (int64_t)q[1], (int64_t)q[2]);
            }
        }
}

static void voxelize_triangle(surf_ctx *c, size_t f)
{
    const uint32_t *tv = hv_mesh_facets(c->mesh) + 3 * f;
    const double *p[3] = {c->P + 3 * (size_t)tv[0], c->P + 3 * (size_t)tv[1], c->P + 3 * (size_t)tv[2]};
    hv_voxel_mark_triangle(p, c->adj26, c->S);
}

static hv_status surf_range(void *ctx, size_t b, size_t e, int thread)
{
    (void)thread;
    for (size_t f = b; f < e; ++f) voxelize_triangle(ctx, f);
    return HV_OK;
}

/* ---- storing the result -------------------------------------------------------------------- */

typedef struct store_ctx {
    const hv_bitgrid *occ, *surf;
    int64_t nb[3];
    /* per block-x slab: the non-empty blocks found */
    size_t *count;
    int32_t **origins;
    uint64_t **masks;
} store_ctx;

static void block_words(const hv_bitgrid *g, int64_t bx, int64_t by, int64_t bz, uint64_t out[8])
{
    int64_t word = (bz * 8) >> 6, shift = (bz * 8) & 63;
    for (int x = 0; x < 8; ++x) {
        uint64_t acc = 0;
        for (int y = 0; y < 8; ++y) {
            uint64_t byte = (hv_bitgrid_row(g, bx * 8 + x, by * 8 + y)[word] >> shift) & 0xFFu;
            acc |= byte << (8 * y);
        }
        out[x] = acc;
    }
}

static hv_status store_slab(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    store_ctx *s = vctx;
    for (size_t bx = b; bx < e; ++bx) {
        size_t cap = 64, n = 0;
        int32_t *o = hv_malloc_array(cap, 3 * sizeof *o);
        uint64_t *m = hv_malloc_array(cap, 8 * sizeof *m);
        if (!o || !m) {
            free(o);
            free(m);
            return HV_ERR_NOMEM;
        }
        for (int64_t by = 0; by < s->nb[1]; ++by)
            for (int64_t bz = 0; bz < s->nb[2]; ++bz) {
                uint64_t w[8];
                block_words(s->occ, (int64_t)bx, by, bz, w);
                if (!(w[0] | w[1] | w[2] | w[3] | w[4] | w[5] | w[6] | w[7])) continue;
                if (n == cap) {
                    cap *= 2;
                    int32_t *o2 = hv_realloc(o, cap * 3 * sizeof *o);
                    if (!o2) {
                        free(o);
                        free(m);
                        return HV_ERR_NOMEM;
                    }
                    o = o2;
                    uint64_t *m2 = hv_realloc(m, cap * 8 * sizeof *m);
                    if (!m2) {
                        free(o);
                        free(m);
                        return HV_ERR_NOMEM;
                    }
                    m = m2;
                }
                o[3 * n] = (int32_t)(s->occ->lo[0] + (int64_t)bx * 8);
                o[3 * n + 1] = (int32_t)(s->occ->lo[1] + by * 8);
                o[3 * n + 2] = (int32_t)(s->occ->lo[2] + bz * 8);
                memcpy(m + 8 * n, w, sizeof w);
                ++n;
            }
        s->count[bx] = n;
        s->origins[bx] = o;
        s->masks[bx] = m;
    }
    return HV_OK;
}

typedef struct fill_ctx {
    hv_volume *vol;
    const hv_bitgrid *surf;
    int g_occ, g_surf;
} fill_ctx;

static hv_status fill_leaves(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    fill_ctx *c = vctx;
    const int32_t *org = hv_volume_leaf_origins(c->vol);
    for (size_t l = b; l < e; ++l) {
        const uint64_t *mask = hv_volume_leaf_mask(c->vol, l);
        uint64_t *occ = hv_volume_leaf_bool(c->vol, c->g_occ, l);
        uint64_t *srf = hv_volume_leaf_bool(c->vol, c->g_surf, l);
        uint64_t w[8];
        block_words(c->surf, (org[3 * l] - c->surf->lo[0]) / 8, (org[3 * l + 1] - c->surf->lo[1]) / 8,
                    (org[3 * l + 2] - c->surf->lo[2]) / 8, w);
        for (int k = 0; k < 8; ++k) {
            occ[k] = mask[k];
            srf[k] = w[k] & mask[k];
        }
    }
    return HV_OK;
}

/* The non-empty 8^3 blocks of g: *total blocks, their origins (3 per block, volume index space)
 * and masks (8 words per block, leaf layout), malloc'd, in ascending (x, y, z) order. */
static hv_status collect_blocks(const hv_bitgrid *g, const hv_progress *progress, size_t *total,
                                int32_t **origins_out, uint64_t **masks_out)
{
    *total = 0;
    *origins_out = NULL;
    *masks_out = NULL;
    store_ctx s = {g, NULL, {g->n[0] / 8, g->n[1] / 8, g->n[2] / 8}, NULL, NULL, NULL};
    size_t nbx = (size_t)s.nb[0];
    s.count = hv_calloc(nbx, sizeof *s.count);
    s.origins = hv_calloc(nbx, sizeof *s.origins);
    s.masks = hv_calloc(nbx, sizeof *s.masks);
    int32_t *origins = NULL;
    uint64_t *masks = NULL;
    hv_status st = HV_OK;
    if (!s.count || !s.origins || !s.masks) {
        st = HV_ERR_NOMEM;
        goto done;
    }
    st = hv_parallel_for(nbx, 1, store_slab, &s, progress, "store");
    if (st != HV_OK) goto done;
    size_t n = 0;
    for (size_t i = 0; i < nbx; ++i) n += s.count[i];
    origins = hv_malloc_array(n ? n : 1, 3 * sizeof *origins);
    masks = hv_malloc_array(n ? n : 1, 8 * sizeof *masks);
    if (!origins || !masks) {
        st = HV_ERR_NOMEM;
        goto done;
    }
    size_t at = 0;
    for (size_t i = 0; i < nbx; ++i) {
        memcpy(origins + 3 * at, s.origins[i], s.count[i] * 3 * sizeof *origins);
        memcpy(masks + 8 * at, s.masks[i], s.count[i] * 8 * sizeof *masks);
        at += s.count[i];
    }
    *total = n;
    *origins_out = origins;
    *masks_out = masks;
    origins = NULL;
    masks = NULL;
done:
    if (s.origins)
        for (size_t i = 0; i < nbx; ++i) {
            free(s.origins[i]);
            free(s.masks[i]);
        }
    free(s.count);
    free(s.origins);
    free(s.masks);
    free(origins);
    free(masks);
    return st;
}

hv_status hv_voxel_store(const hv_bitgrid *occ, const hv_bitgrid *surf, const hv_transform *xf,
                       const hv_progress *progress, hv_volume **out)
{
    *out = NULL;
    hv_volume *vol = NULL;
    int32_t *origins = NULL;
    uint64_t *masks = NULL;
    size_t total;
    hv_status st = collect_blocks(occ, progress, &total, &origins, &masks);
    if (st != HV_OK) goto done;
    if ((st = hv_volume_create(xf, &vol)) != HV_OK) goto done;
    int g_occ, g_surf;
    if ((st = hv_volume_grid_add(vol, "occupancy", HV_GRID_BOOL, &g_occ)) != HV_OK ||
        (st = hv_volume_grid_add(vol, "surface", HV_GRID_BOOL, &g_surf)) != HV_OK ||
        (st = hv_volume_topology_add(vol, total, origins, masks)) != HV_OK)
        goto done;
    free(origins);
    free(masks);
    origins = NULL;
    masks = NULL;
    fill_ctx fc = {vol, surf, g_occ, g_surf};
    st = hv_parallel_for(hv_volume_leaf_count(vol), 256, fill_leaves, &fc, NULL, "store");
    if (st != HV_OK) goto done;
    *out = vol;
    vol = NULL;
done:
    free(origins);
    free(masks);
    hv_volume_destroy(vol);
    return st;
}

/* ---- entry ---------------------------------------------------------------------------------- */

json_t *hv_voxelize_to_doc(const hv_voxel_plan *plan, int adjacency)
{
    return json_pack("{s:i, s:s, s:[I, I, I], s:[I, I, I], s:o}", "adjacency", adjacency, "fill",
                     hv_fill_mode_name(plan->fill), "first", (json_int_t)plan->first[0],
                     (json_int_t)plan->first[1], (json_int_t)plan->first[2], "dims", (json_int_t)plan->dims[0],
                     (json_int_t)plan->dims[1], (json_int_t)plan->dims[2], "voxel",
                     hv_json_numbers(plan->xf.voxel, 3));
}

/* Three integers in [lo, hi]. */
static hv_status index_triple(const json_t *doc, const char *key, const char *what, double lo, double hi,
                              int64_t *out)
{
    double v[3];
    hv_status s = hv_json_get_numbers(doc, key, what, v, 3);
    for (int a = 0; a < 3 && s == HV_OK; ++a) {
        if (v[a] != floor(v[a]) || v[a] < lo || v[a] > hi)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s[%d] is %.17g, not an integer in [%.0f, %.0f]", what, key, a,
                                v[a], lo, hi);
        out[a] = (int64_t)v[a];
    }
    return s;
}

hv_status hv_voxelize_from_doc(const json_t *doc, const char *what, hv_voxelize_record *rec)
{
    long long adj;
    int fill;
    hv_status s = hv_json_get_int(doc, "adjacency", what, 6, 26, &adj);
    if (s == HV_OK && adj != 6 && adj != 26)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: adjacency is %lld, not 6 or 26", what, adj);
    if (s == HV_OK) s = hv_json_get_name(doc, "fill", what, hv_fill_mode_enum(), &fill);
    if (s == HV_OK) s = index_triple(doc, "first", what, -2147483648.0, 2147483647.0, rec->first);
    if (s == HV_OK) s = index_triple(doc, "dims", what, 1, 2147483648.0, rec->dims);
    if (s == HV_OK) s = hv_json_get_numbers(doc, "voxel", what, rec->voxel, 3);
    for (int a = 0; a < 3 && s == HV_OK; ++a)
        if (!(rec->voxel[a] > 0))
            s = hv_error_set(HV_ERR_BAD_INPUT, "%s: voxel[%d] is %.17g, not > 0", what, a, rec->voxel[a]);
    if (s == HV_OK) {
        rec->adjacency = (int)adj;
        rec->fill = (hv_fill_mode)fill;
    }
    return s;
}

hv_status hv_voxelize_record_read(const hv_volume *model, hv_voxelize_record *out)
{
    memset(out, 0, sizeof *out);
    json_t *mesh = NULL, *job = NULL;
    hv_status s = hv_schema_doc_read(model, HV_DOC_MESH, &mesh);
    if (s == HV_OK) s = hv_schema_doc_read(model, HV_DOC_VOXELIZE, &job);
    if (s == HV_OK) s = hv_mesh_report_from_doc(mesh, hv_schema_key(HV_DOC_MESH), &out->mesh);
    if (s == HV_OK) s = hv_voxelize_from_doc(job, hv_schema_key(HV_DOC_VOXELIZE), out);
    json_decref(mesh);
    json_decref(job);
    return s;
}

static hv_status set_metadata(hv_volume *vol, const hv_mesh *mesh, const hv_voxel_plan *plan,
                              int adjacency)
{
    hv_status s = hv_schema_doc_write(vol, HV_DOC_MESH, hv_mesh_report_to_doc(hv_mesh_name(mesh), hv_mesh_get_report(mesh)));
    if (s == HV_OK) s = hv_schema_doc_write(vol, HV_DOC_VOXELIZE, hv_voxelize_to_doc(plan, adjacency));
    if (s == HV_OK) s = hv_volume_meta_set_string(vol, HV_META_HOVOX_VERSION, hv_version());
    /* the geometry truth (issue 28): the mesh itself, so every later stage cuts the exact shape */
    hv_geometry *g = NULL;
    if (s == HV_OK) s = hv_geometry_from_mesh(mesh, NULL, NULL, 1.0, &g);
    if (s == HV_OK) s = hv_geometry_write(g, vol);
    hv_geometry_destroy(g);
    return s;
}

size_t mesh_bytes(const hv_mesh *m)
{
    return hv_mesh_vertex_count(m) * 12 + hv_mesh_facet_count(m) * 25;
}

/* ---- assemblies ------------------------------------------------------------------------------ */

typedef struct region_work {
    size_t n;          /* the region's voxels as leaf blocks */
    int32_t *origins;
    uint64_t *masks;
} region_work;

/* The part of the job's grid (lo, n) a body needs: its vertices' index box plus PAD, aligned to 8
 * in x and y (so blocks are leaves) and to 64 in z relative to the grid (so rows map word to
 * word). */
static void body_box(const hv_mesh *bm, const hv_voxel_plan *p, const int64_t lo[3], const int64_t n[3],
                     int64_t blo[3], int64_t bn[3])
{
    const float *xyz = hv_mesh_vertices(bm);
    size_t nv = hv_mesh_vertex_count(bm);
    for (int a = 0; a < 3; ++a) {
        double mn = INFINITY, mx = -INFINITY;
        for (size_t i = 0; i < nv; ++i) {
            double q = ((double)xyz[3 * i + (size_t)a] - p->xf.origin[a]) / p->xf.voxel[a];
            mn = HV_MIN(mn, q);
            mx = HV_MAX(mx, q);
        }
        int64_t l = (int64_t)floor(mn) - PAD, h = (int64_t)ceil(mx) + PAD;
        l = HV_MAX(l, lo[a]);
        h = HV_MIN(h, lo[a] + n[a] - 1);
        int64_t align = a == 2 ? 64 : 8;
        blo[a] = lo[a] + (l - lo[a]) / align * align;
        bn[a] = HV_MIN(round_up8(h + 1 - blo[a]), lo[a] + n[a] - blo[a]);
    }
}

/* One body alone on the body's part of the grid: its surface S, occupancy O and centre set C (the
 * voxels of O whose centre is inside the body: O's interior, which every fill puts inside only
 * where it is, and the surface voxels whose centres the vote's parities put inside). */
static hv_status body_voxels(const hv_mesh *bm, const hv_voxel_plan *p, const hv_voxelize_options *opt,
                             hv_fill_mode fill, const int64_t blo[3], const int64_t bn[3], hv_bitgrid *S, hv_bitgrid *O,
                             hv_bitgrid *C)
{
    size_t nv = hv_mesh_vertex_count(bm);
    double *P = hv_malloc_array(nv, 3 * sizeof *P);
    hv_status s = P ? hv_bitgrid_init(S, bn, blo) : HV_ERR_NOMEM;
    if (s == HV_OK) {
        const float *xyz = hv_mesh_vertices(bm);
        for (size_t i = 0; i < nv; ++i)
            for (int a = 0; a < 3; ++a)
                P[3 * i + (size_t)a] = ((double)xyz[3 * i + (size_t)a] - p->xf.origin[a]) / p->xf.voxel[a] - (double)blo[a];
        surf_ctx sc = {bm, P, S, opt->adjacency == 26};
        s = hv_parallel_for(hv_mesh_facet_count(bm), 512, surf_range, &sc, opt->progress, "surface");
    }
    if (s == HV_OK) s = hv_bitgrid_init(O, bn, blo);
    if (s == HV_OK) s = hv_bitgrid_init(C, bn, blo);
    /* the vote of every voxel's centre; the vote fill is that plus the surface */
    if (s == HV_OK) s = hv_fill_centres(bm, P, C, opt->progress);
    size_t words = (size_t)(bn[0] * bn[1] * S->words);
    if (s == HV_OK) {
        switch (fill) {
        case HV_FILL_FLOOD: s = hv_fill_flood(S, O, opt->adjacency, opt->progress); break;
        case HV_FILL_VOTE:
            for (size_t w = 0; w < words; ++w) O->bits[w] = C->bits[w] | S->bits[w];
            break;
        default: memcpy(O->bits, S->bits, words * sizeof(uint64_t)); break;
        }
    }
    if (s == HV_OK)
        for (size_t w = 0; w < words; ++w)
            C->bits[w] = (O->bits[w] & ~S->bits[w]) | (S->bits[w] & C->bits[w]);
    free(P);
    return s;
}

/* Voxels of body grid C that earlier region j took in the first pass (its blocks inside C's box). */
static uint64_t overlap_with(const hv_bitgrid *C, const region_work *rj)
{
    uint64_t n = 0;
    for (size_t b = 0; b < rj->n; ++b) {
        const int32_t *o = rj->origins + 3 * b;
        int64_t d[3];
        int inside = 1;
        for (int a = 0; a < 3; ++a) {
            d[a] = (int64_t)o[a] - C->lo[a];
            if (d[a] < 0 || d[a] >= C->n[a]) inside = 0;
        }
        if (!inside) continue;
        uint64_t w[8];
        block_words(C, d[0] / 8, d[1] / 8, d[2] / 8, w);
        for (int k = 0; k < 8; ++k) n += (uint64_t)__builtin_popcountll(w[k] & rj->masks[8 * b + (size_t)k]);
    }
    return n;
}

/* OR a block's 8 words (leaf layout) into grid g at block (bx, by, bz). */
static void block_or(hv_bitgrid *g, int64_t bx, int64_t by, int64_t bz, const uint64_t m[8])
{
    int64_t word = (bz * 8) >> 6, shift = (bz * 8) & 63;
    for (int x = 0; x < 8; ++x)
        for (int y = 0; y < 8; ++y)
            hv_bitgrid_row(g, bx * 8 + x, by * 8 + y)[word] |= ((m[x] >> (8 * y)) & 0xFFu) << shift;
}

/* The union grids of an assembly, on the job's grid. */
typedef struct union_grids {
    hv_bitgrid U;  /* occupancy: the union of the bodies' O */
    hv_bitgrid SU; /* the bodies' surfaces */
    hv_bitgrid IU; /* the bodies' interiors (O minus S); then the second pass's claimed voxels */
    hv_bitgrid CU; /* centres inside some body */
    hv_bitgrid C2; /* centres inside two or more bodies */
} union_grids;

/* Fold a body's grids into the unions. C is left holding the body's first-pass voxels (centres
 * inside it and in no earlier body), O the candidates of the second pass (its voxels whose
 * centres are not inside it). Counts the body's occupied voxels and first-pass voxels. */
static void fold_body(hv_bitgrid *O, const hv_bitgrid *S, hv_bitgrid *C, union_grids *u, uint64_t *nocc, uint64_t *nfirst)
{
    int64_t di = O->lo[0] - u->U.lo[0], dj = O->lo[1] - u->U.lo[1], dw = (O->lo[2] - u->U.lo[2]) / 64;
    for (int64_t i = 0; i < O->n[0]; ++i)
        for (int64_t j = 0; j < O->n[1]; ++j) {
            uint64_t *o = hv_bitgrid_row(O, i, j), *c = hv_bitgrid_row(C, i, j);
            const uint64_t *sb = hv_bitgrid_row(S, i, j);
            int64_t gi = i + di, gj = j + dj;
            uint64_t *uu = hv_bitgrid_row(&u->U, gi, gj) + dw, *su = hv_bitgrid_row(&u->SU, gi, gj) + dw,
                     *iu = hv_bitgrid_row(&u->IU, gi, gj) + dw, *cu = hv_bitgrid_row(&u->CU, gi, gj) + dw,
                     *c2 = hv_bitgrid_row(&u->C2, gi, gj) + dw;
            for (int64_t w = 0; w < O->words; ++w) {
                uint64_t valid = hv_bitgrid_valid(O, w), occ = o[w] & valid, srf = sb[w] & valid, in = c[w] & occ;
                *nocc += (uint64_t)__builtin_popcountll(occ);
                uu[w] |= occ;
                su[w] |= srf;
                iu[w] |= occ & ~srf;
                c2[w] |= in & cu[w];
                c[w] = in & ~cu[w];
                cu[w] |= in;
                o[w] = occ & ~in;
                *nfirst += (uint64_t)__builtin_popcountll(c[w]);
            }
        }
}

/* Flood only where it is exact: one closed, manifold, consistently oriented shell. Several shells
 * may nest (a hollow part: an outer shell and an inward-facing cavity), and flooding from the
 * border would fill the cavity; the vote's ray parities leave it empty. */
hv_fill_mode hv_fill_auto(const hv_mesh_report *r)
{
    return r->open_edges == 0 && r->nonmanifold_edges == 0 && r->flipped_facets == 0 && r->shells <= 1
               ? HV_FILL_FLOOD
               : HV_FILL_VOTE;
}

static void union_free(union_grids *u)
{
    hv_bitgrid_free(&u->U);
    hv_bitgrid_free(&u->SU);
    hv_bitgrid_free(&u->IU);
    hv_bitgrid_free(&u->CU);
    hv_bitgrid_free(&u->C2);
}

static uint64_t grid_count(const hv_bitgrid *g)
{
    uint64_t n = 0;
    for (size_t w = 0; w < (size_t)(g->n[0] * g->n[1] * g->words); ++w) n += (uint64_t)__builtin_popcountll(g->bits[w]);
    return n;
}

/* Write region b's blocks into bool grid g of vol (OR: a region comes in two block lists). */
static hv_status region_write(hv_volume *vol, int g, const region_work *r, const char *grid)
{
    hv_accessor acc;
    hv_accessor_init(&acc, vol);
    for (size_t k = 0; k < r->n; ++k) {
        const int32_t *o = r->origins + 3 * k;
        const uint64_t *m = r->masks + 8 * k;
        if (!(m[0] | m[1] | m[2] | m[3] | m[4] | m[5] | m[6] | m[7])) continue;
        int64_t leaf = hv_accessor_leaf(&acc, o[0], o[1], o[2]);
        if (leaf < 0) return hv_error_set(HV_ERR_INTERNAL, "voxelize: region %s has voxels outside the occupancy", grid);
        uint64_t *bits = hv_volume_leaf_bool(vol, g, (size_t)leaf);
        const uint64_t *mask = hv_volume_leaf_mask(vol, (size_t)leaf);
        for (int q = 0; q < 8; ++q) bits[q] |= m[q] & mask[q];
    }
    return HV_OK;
}

/* A body on its way through voxelize_bodies: its mesh, box and grids (body_voxels). */
typedef struct body_job {
    hv_mesh *bm;
    int64_t blo[3], bn[3];
    hv_bitgrid S, O, C;
} body_job;

static void body_job_free(body_job *j)
{
    hv_mesh_destroy(j->bm);
    hv_bitgrid_free(&j->S);
    hv_bitgrid_free(&j->O);
    hv_bitgrid_free(&j->C);
    memset(j, 0, sizeof *j);
}

/* Body b alone: its region record (name, material, colour, fill), its mesh, box and grids.
 * Thread-safe for distinct bodies. */
static hv_status body_run(const hv_mesh *mesh, size_t b, const hv_voxelize_options *opt, const hv_voxel_plan *plan,
                          const int64_t lo[3], const int64_t n[3], hv_region_info *g, body_job *j)
{
    memset(j, 0, sizeof *j);
    const hv_mesh_body *body = hv_mesh_body_at(mesh, b);
    hv_status s = hv_mesh_body_extract(mesh, b, &j->bm);
    if (s == HV_OK && (!(g->name = hv_strdup(body->name)) ||
                       (body->material != HV_MESH_NO_MATERIAL &&
                        !(g->material = hv_strdup(hv_mesh_material_at(mesh, (size_t)body->material)->name)))))
        s = HV_ERR_NOMEM;
    if (s == HV_OK) s = hv_regions_grid_name(body->name, (char **)&g->grid);
    if (s != HV_OK) return s;
    if (body->material != HV_MESH_NO_MATERIAL) {
        const hv_mesh_material *mm = hv_mesh_material_at(mesh, (size_t)body->material);
        if ((g->has_color = mm->has_color))
            for (int k = 0; k < 4; ++k) g->rgba[k] = (float)((mm->rgba >> (24 - 8 * k)) & 0xFFu) / 255.0f;
        hv_mesh_mix_part *p = mm->nparts ? hv_calloc(mm->nparts, sizeof *p) : NULL;
        if (mm->nparts && !p) return HV_ERR_NOMEM;
        g->parts = p;
        for (size_t k = 0; k < mm->nparts; ++k) {
            if (!(p[k].material = hv_strdup(mm->parts[k].material))) return HV_ERR_NOMEM;
            p[k].fraction = mm->parts[k].fraction;
            g->nparts = k + 1;
        }
    }
    g->fill = opt->fill == HV_FILL_AUTO ? hv_fill_auto(hv_mesh_get_report(j->bm)) : opt->fill;
    body_box(j->bm, plan, lo, n, j->blo, j->bn);
    return body_voxels(j->bm, plan, opt, g->fill, j->blo, j->bn, &j->S, &j->O, &j->C);
}

/* Small enough to run on one thread beside others: few facets and a box of a few MiB of bits
 * (the box of its facets' vertices, as body_box finds it). */
static int body_small(const hv_mesh *mesh, size_t b, const hv_voxel_plan *p, const int64_t lo[3], const int64_t n[3])
{
    const hv_mesh_body *body = hv_mesh_body_at(mesh, b);
    if (body->facet_count > 65536) return 0;
    const uint32_t *tri = hv_mesh_facets(mesh);
    const float *xyz = hv_mesh_vertices(mesh);
    double voxels = 1;
    for (int a = 0; a < 3; ++a) {
        double mn = INFINITY, mx = -INFINITY;
        for (size_t f = body->first_facet; f < body->first_facet + body->facet_count; ++f)
            for (int k = 0; k < 3; ++k) {
                double q = ((double)xyz[3 * (size_t)tri[3 * f + (size_t)k] + (size_t)a] - p->xf.origin[a]) / p->xf.voxel[a];
                mn = HV_MIN(mn, q);
                mx = HV_MAX(mx, q);
            }
        double span = HV_MIN(mx + PAD + 1, (double)(lo[a] + n[a])) - HV_MAX(mn - PAD, (double)lo[a]) + 64;
        voxels *= HV_MAX(span, 1.0);
    }
    return voxels <= (double)(1 << 24);
}

/* Fold body b's grids into the unions, in file order (the first body keeps the overlap), and keep
 * its first-pass voxels and second-pass candidates as blocks. */
static hv_status body_fold(body_job *j, size_t b, union_grids *u, region_work *rw, region_work *rk, uint64_t *nocc,
                           hv_region_info *g)
{
    /* the overlap: this body's centres that an earlier body took in the first pass */
    hv_region_loss *to = NULL;
    for (size_t q = 0; q < b; ++q) {
        uint64_t cnt = overlap_with(&j->C, &rw[q]);
        if (!cnt) continue;
        if (!to && !(to = hv_calloc(b, sizeof *to))) return HV_ERR_NOMEM;
        g->lost_to = to;
        to[g->nlost_to].region = q;
        to[g->nlost_to++].voxels = cnt;
    }
    uint64_t first = 0;
    fold_body(&j->O, &j->S, &j->C, u, &nocc[b], &first);
    hv_bitgrid_free(&j->S);
    g->voxels = first;
    hv_status s = collect_blocks(&j->C, NULL, &rw[b].n, &rw[b].origins, &rw[b].masks);
    hv_bitgrid_free(&j->C);
    if (s == HV_OK) s = collect_blocks(&j->O, NULL, &rk[b].n, &rk[b].origins, &rk[b].masks);
    return s;
}

/* The bodies of an assembly on one lattice. A voxel belongs to the body that contains its centre,
 * in two passes in file order: (1) a voxel whose centre is inside one or more bodies goes to the
 * first of them; (2) a voxel left (the outer skin: in some body's occupancy, its centre in none)
 * goes to the first body whose occupancy holds it. Pass 1 runs as the bodies come; pass 2 needs
 * every body's centres, so each body keeps its candidates as leaf blocks until the end. */
static hv_status voxelize_bodies(const hv_mesh *mesh, const hv_voxelize_options *opt, const hv_voxel_plan *plan,
                                 hv_volume **out)
{
    size_t nb = hv_mesh_body_count(mesh);
    int64_t n[3], lo[3];
    grid_box(plan, lo, n);
    union_grids u;
    memset(&u, 0, sizeof u);
    region_work *rw = hv_calloc(nb, sizeof *rw), *rk = hv_calloc(nb, sizeof *rk); /* pass 1 voxels, pass 2 candidates */
    uint64_t *nocc = hv_calloc(nb, sizeof *nocc);
    hv_regions *regs = hv_calloc(1, sizeof *regs);
    hv_volume *vol = NULL;
    hv_status s = rw && rk && nocc && regs && (regs->info = hv_calloc(nb, sizeof *regs->info)) ? HV_OK : HV_ERR_NOMEM;
    if (s == HV_OK) s = hv_bitgrid_init(&u.U, n, lo);
    if (s == HV_OK) s = hv_bitgrid_init(&u.SU, n, lo);
    if (s == HV_OK) s = hv_bitgrid_init(&u.IU, n, lo);
    if (s == HV_OK) s = hv_bitgrid_init(&u.CU, n, lo);
    if (s == HV_OK) s = hv_bitgrid_init(&u.C2, n, lo);
    int fills = 0; /* bit per resolved fill mode */
    if (s == HV_OK) regs->n = nb; /* records filled as the bodies come (calloc'd: freed whatever happens) */
    hv_voxelize_options quiet = *opt;
    quiet.progress = NULL;
    for (size_t b = 0; b < nb && s == HV_OK;) {
        /* a run of small bodies, a thread each, folded in file order (an assembly of many small
         * bodies pays no fork and join per body and loop: issue 32 item 20); a large body alone,
         * its loops parallel */
        size_t e = b;
        while (e < nb && body_small(mesh, e, plan, lo, n)) ++e;
        if (e == b) {
            body_job j;
            s = body_run(mesh, b, opt, plan, lo, n, &regs->info[b], &j);
            if (s == HV_OK) fills |= 1 << regs->info[b].fill;
            if (s == HV_OK) s = body_fold(&j, b, &u, rw, rk, nocc, &regs->info[b]);
            body_job_free(&j);
            ++b;
            continue;
        }
        atomic_int stop = 0;
        hv_status run_status = HV_OK;
#pragma omp parallel for ordered schedule(dynamic, 1) num_threads(hv_threads())
        for (size_t k = b; k < e; ++k) {
            body_job j;
            memset(&j, 0, sizeof j);
            hv_status st = atomic_load(&stop) ? HV_ERR_CANCELLED
                                              : body_run(mesh, k, &quiet, plan, lo, n, &regs->info[k], &j);
            char msg[512] = "";
            if (st != HV_OK) snprintf(msg, sizeof msg, "%s", hv_last_error());
#pragma omp ordered
            {
                if (run_status == HV_OK && st != HV_OK) {
                    run_status = hv_error_set(st, "%s", msg);
                    atomic_store(&stop, 1);
                }
                if (run_status == HV_OK) {
                    fills |= 1 << regs->info[k].fill;
                    st = body_fold(&j, k, &u, rw, rk, nocc, &regs->info[k]);
                    if (st != HV_OK) {
                        run_status = st;
                        snprintf(msg, sizeof msg, "%s", hv_last_error());
                        hv_error_set(st, "%s", msg);
                        atomic_store(&stop, 1);
                    }
                }
            }
            body_job_free(&j);
        }
        if (run_status != HV_OK) { /* the message was set on the thread that failed: again here */
            s = run_status;
            break;
        }
        b = e;
        s = hv_progress_report(opt->progress, "bodies", (double)b / (double)nb);
    }
    if (s == HV_OK) {
        /* the surface of the union: surface voxels inside no body's interior */
        size_t words = (size_t)(n[0] * n[1] * u.SU.words);
        for (size_t w = 0; w < words; ++w) u.SU.bits[w] &= ~u.IU.bits[w];
        /* the second pass, IU now holding the voxels it gave away */
        memset(u.IU.bits, 0, words * sizeof *u.IU.bits);
        for (size_t b = 0; b < nb; ++b) {
            for (size_t k = 0; k < rk[b].n; ++k) {
                const int32_t *o = rk[b].origins + 3 * k;
                uint64_t *m = rk[b].masks + 8 * k, cu[8], taken[8];
                int64_t bx = (o[0] - lo[0]) / 8, by = (o[1] - lo[1]) / 8, bz = (o[2] - lo[2]) / 8;
                block_words(&u.CU, bx, by, bz, cu);
                block_words(&u.IU, bx, by, bz, taken);
                for (int q = 0; q < 8; ++q) {
                    m[q] &= ~cu[q] & ~taken[q];
                    regs->info[b].voxels += (uint64_t)__builtin_popcountll(m[q]);
                }
                block_or(&u.IU, bx, by, bz, m);
            }
            regs->info[b].lost = nocc[b] - regs->info[b].voxels;
        }
        regs->overlap = grid_count(&u.C2);
        hv_bitgrid_free(&u.IU);
        hv_bitgrid_free(&u.CU);
        hv_bitgrid_free(&u.C2);
        s = hv_voxel_store(&u.U, &u.SU, &plan->xf, opt->progress, &vol);
    }
    for (size_t b = 0; b < nb && s == HV_OK; ++b) {
        int g;
        s = hv_volume_grid_add(vol, regs->info[b].grid, HV_GRID_BOOL, &g);
        if (s == HV_OK) s = region_write(vol, g, &rw[b], regs->info[b].grid);
        if (s == HV_OK) s = region_write(vol, g, &rk[b], regs->info[b].grid);
    }
    if (s == HV_OK) {
        hv_voxel_plan rec = *plan; /* the fill as resolved, when every body resolved alike */
        rec.fill = (fills & (fills - 1)) == 0 ? (hv_fill_mode)__builtin_ctz((unsigned)fills) : HV_FILL_AUTO;
        s = set_metadata(vol, mesh, &rec, opt->adjacency);
        if (s == HV_OK)
            s = hv_schema_doc_write(vol, HV_DOC_REGIONS,
                                    hv_regions_to_doc(regs, plan->xf.voxel[0] * plan->xf.voxel[1] * plan->xf.voxel[2]));
    }
    if (s == HV_OK) {
        *out = vol;
        vol = NULL;
    }
    hv_volume_destroy(vol);
    for (size_t b = 0; b < nb; ++b) {
        if (rw) {
            free(rw[b].origins);
            free(rw[b].masks);
        }
        if (rk) {
            free(rk[b].origins);
            free(rk[b].masks);
        }
    }
    free(rw);
    free(rk);
    free(nocc);
    hv_regions_destroy(regs);
    union_free(&u);
    return s;
}

hv_status hv_voxelize(const hv_mesh *mesh, const hv_voxelize_options *opt, hv_volume **out)
{
    *out = NULL;
    hv_voxel_plan plan;
    hv_status s = hv_voxelize_plan(mesh, opt, &plan);
    if (s != HV_OK) return s;
    if (hv_mesh_body_count(mesh) > 1) return voxelize_bodies(mesh, opt, &plan, out);
    int64_t n[3], lo[3];
    grid_box(&plan, lo, n);
    hv_bitgrid S = {0}, occ = {0};
    double *P = NULL;
    if ((s = hv_bitgrid_init(&S, n, lo)) != HV_OK) goto done;
    size_t nv = hv_mesh_vertex_count(mesh);
    P = hv_malloc_array(nv, 3 * sizeof *P);
    if (!P) {
        s = HV_ERR_NOMEM;
        goto done;
    }
    const float *xyz = hv_mesh_vertices(mesh);
    for (size_t i = 0; i < nv; ++i)
        for (int a = 0; a < 3; ++a)
            P[3 * i + (size_t)a] = ((double)xyz[3 * i + (size_t)a] - plan.xf.origin[a]) / plan.xf.voxel[a] - (double)lo[a];
    surf_ctx sc = {mesh, P, &S, opt->adjacency == 26};
    s = hv_parallel_for(hv_mesh_facet_count(mesh), 512, surf_range, &sc, opt->progress, "surface");
    if (s != HV_OK) goto done;
    if ((s = hv_bitgrid_init(&occ, n, lo)) != HV_OK) goto done;
    switch (plan.fill) {
    case HV_FILL_FLOOD: s = hv_fill_flood(&S, &occ, opt->adjacency, opt->progress); break;
    case HV_FILL_VOTE: s = hv_fill_vote(mesh, P, &S, &occ, opt->progress); break;
    default: memcpy(occ.bits, S.bits, (size_t)(n[0] * n[1] * S.words) * sizeof(uint64_t)); break;
    }
    if (s != HV_OK) goto done;
    free(P);
    P = NULL;
    hv_volume *vol = NULL;
    s = hv_voxel_store(&occ, &S, &plan.xf, opt->progress, &vol);
    if (s != HV_OK) goto done;
    s = set_metadata(vol, mesh, &plan, opt->adjacency);
    if (s != HV_OK) {
        hv_volume_destroy(vol);
        goto done;
    }
    *out = vol;
done:
    free(P);
    hv_bitgrid_free(&S);
    hv_bitgrid_free(&occ);
    return s;
}
