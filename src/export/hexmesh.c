/* src/export/hexmesh.c - the .vtu hexahedral mesh of a sparse model: one VTK_HEXAHEDRON per
 * occupied voxel, or per NxNxN block kept by the coarsening rule, with corner points shared
 * between neighbours. Cells and corners live in 8x8x8 leaf blocks like the volume; a corner
 * is owned by the block of its lattice index, so every point is numbered once, by a prefix sum
 * over sorted blocks, without a global hash of points. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "export_internal.h"

/* ---- blocks of 8x8x8 cells or corners: sorted origins and an origin -> block hash ------- */

static int cmp_origin(const void *a, const void *b)
{
    const int32_t *x = a, *y = b;
    for (int q = 0; q < 3; ++q)
        if (x[q] != y[q]) return x[q] < y[q] ? -1 : 1;
    return 0;
}

/* Sort n origins and drop duplicates; returns the new count. */
static size_t sort_unique(int32_t *o, size_t n)
{
    if (n == 0) return 0;
    qsort(o, n, 3 * sizeof *o, cmp_origin);
    size_t k = 1;
    for (size_t i = 1; i < n; ++i)
        if (cmp_origin(o + 3 * i, o + 3 * (k - 1)) != 0) {
            memmove(o + 3 * k, o + 3 * i, 3 * sizeof *o);
            ++k;
        }
    return k;
}

static uint64_t hash3(int32_t x, int32_t y, int32_t z)
{
    uint64_t h = (uint64_t)(uint32_t)(x >> 3) * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t)(uint32_t)(y >> 3) * 0xC2B2AE3D27D4EB4Full;
    h ^= (uint64_t)(uint32_t)(z >> 3) * 0x165667B19E3779F9ull;
    return h ^ (h >> 29);
}

static hv_status hash_build(const int32_t *o, size_t n, int64_t **tab, size_t *cap)
{
    size_t c = 16;
    while (c < 2 * n) c *= 2;
    int64_t *t = hv_malloc_array(c, sizeof *t);
    if (!t) return HV_ERR_NOMEM;
    for (size_t i = 0; i < c; ++i) t[i] = -1;
    for (size_t i = 0; i < n; ++i) {
        size_t s = (size_t)hash3(o[3 * i], o[3 * i + 1], o[3 * i + 2]) & (c - 1);
        while (t[s] >= 0) s = (s + 1) & (c - 1);
        t[s] = (int64_t)i;
    }
    *tab = t;
    *cap = c;
    return HV_OK;
}

static int64_t hash_find(const int32_t *o, const int64_t *t, size_t cap, int32_t x, int32_t y,
                         int32_t z)
{
    for (size_t s = (size_t)hash3(x, y, z) & (cap - 1);; s = (s + 1) & (cap - 1)) {
        int64_t i = t[s];
        if (i < 0) return -1;
        const int32_t *p = o + 3 * i;
        if (p[0] == x && p[1] == y && p[2] == z) return i;
    }
}

static int32_t floor_div(int32_t a, int32_t b)
{
    return a >= 0 ? a / b : -(int32_t)(((int64_t)-a + b - 1) / b);
}

static int any_bit(const uint64_t *w)
{
    return (w[0] | w[1] | w[2] | w[3] | w[4] | w[5] | w[6] | w[7]) != 0;
}

/* ---- cells -------------------------------------------------------------------------------- */

static int kept(const ex_hexmesh *h, int64_t count)
{
    if (h->rule == HV_COARSEN_ANY) return count > 0;
    return 2 * count >= (int64_t)h->n * h->n * h->n;
}

typedef struct plan_ctx {
    ex_hexmesh *h;
    const ex_model *md;
    int64_t *count; /* 512 per coarse block: occupied voxels of each coarse cell */
} plan_ctx;

/* Count the occupied voxels of every coarse cell by visiting the occupied voxels once (not
 * the N^3 voxels of every cell: empty space costs nothing, whatever N). */
static hv_status count_range(void *ctx, size_t b, size_t e, int thread)
{
    (void)thread;
    plan_ctx *c = ctx;
    const ex_hexmesh *h = c->h;
    const int32_t *orig = hv_volume_leaf_origins(c->md->vol);
    int32_t n = h->n, last[3] = {INT32_MIN, 0, 0};
    int64_t L = -1;
    for (size_t l = b; l < e; ++l) {
        const uint64_t *w = c->md->occ + 8 * l;
        const int32_t *o = orig + 3 * l;
        for (int q = 0; q < 8; ++q)
            for (uint64_t u = w[q]; u; u &= u - 1) {
                unsigned bit = (unsigned)(64 * q + __builtin_ctzll(u));
                int32_t v[3] = {o[0] + (int32_t)(bit >> 6), o[1] + (int32_t)((bit >> 3) & 7),
                                o[2] + (int32_t)(bit & 7)};
                int32_t cc[3], blk[3];
                for (int a = 0; a < 3; ++a) {
                    cc[a] = floor_div(v[a], n);
                    blk[a] = cc[a] & ~7;
                }
                if (blk[0] != last[0] || blk[1] != last[1] || blk[2] != last[2]) {
                    L = hash_find(h->cl_origin, h->clh, h->clh_cap, blk[0], blk[1], blk[2]);
                    memcpy(last, blk, sizeof last);
                }
                if (L < 0) continue; /* cannot happen: every touched block is listed */
                unsigned cq = (unsigned)(((cc[0] & 7) << 6) | ((cc[1] & 7) << 3) | (cc[2] & 7));
                __atomic_fetch_add(&c->count[512 * (size_t)L + cq], 1, __ATOMIC_RELAXED);
            }
    }
    return HV_OK;
}

static hv_status cells_range(void *ctx, size_t b, size_t e, int thread)
{
    (void)thread;
    plan_ctx *c = ctx;
    ex_hexmesh *h = c->h;
    for (size_t L = b; L < e; ++L) {
        uint64_t *w = h->cl_mask + 8 * L;
        for (unsigned q = 0; q < HV_LEAF_SIZE; ++q)
            if (kept(h, c->count[512 * L + q])) w[q >> 6] |= 1ull << (q & 63);
    }
    return HV_OK;
}

/* A corner is used when one of the 8 cells around it (corner - {0,1}^3) is kept. */
static hv_status corners_range(void *ctx, size_t b, size_t e, int thread)
{
    (void)thread;
    plan_ctx *c = ctx;
    ex_hexmesh *h = c->h;
    for (size_t K = b; K < e; ++K) {
        const int32_t *o = h->kl_origin + 3 * K;
        const uint64_t *nb[8];
        for (int d = 0; d < 8; ++d) {
            int64_t L = hash_find(h->cl_origin, h->clh, h->clh_cap, o[0] - 8 * ((d >> 2) & 1),
                                  o[1] - 8 * ((d >> 1) & 1), o[2] - 8 * (d & 1));
            nb[d] = L >= 0 ? h->cl_mask + 8 * L : NULL;
        }
        uint64_t *w = h->kl_mask + 8 * K;
        for (int x = 0; x < 8; ++x)
            for (int y = 0; y < 8; ++y)
                for (int z = 0; z < 8; ++z) {
                    int used = 0;
                    for (int e3 = 0; e3 < 8 && !used; ++e3) {
                        int cx = x - ((e3 >> 2) & 1), cy = y - ((e3 >> 1) & 1), cz = z - (e3 & 1);
                        int d = ((cx < 0) << 2) | ((cy < 0) << 1) | (cz < 0);
                        if (nb[d]) used = (int)HV_BIT_GET(nb[d], HV_LEAF_OFFSET(cx, cy, cz));
                    }
                    if (used) {
                        unsigned q = HV_LEAF_OFFSET(x, y, z);
                        w[q >> 6] |= 1ull << (q & 63);
                    }
                }
    }
    return HV_OK;
}

void ex_hexmesh_free(ex_hexmesh *h)
{
    if (!h) return;
    free(h->cl_origin);
    free(h->kl_origin);
    free(h->cl_mask);
    free(h->kl_mask);
    free(h->cl_base);
    free(h->kl_base);
    free(h->kl_prefix);
    free(h->clh);
    free(h->klh);
    memset(h, 0, sizeof *h);
}

hv_status ex_hexmesh_plan(ex_hexmesh *h, const ex_model *md, int n, hv_coarsen_rule rule,
                          const hv_progress *progress)
{
    memset(h, 0, sizeof *h);
    h->n = n;
    h->rule = rule;
    const int32_t *orig = hv_volume_leaf_origins(md->vol);

    /* coarse-cell blocks touched by voxel leaves that hold exported voxels: per axis the
     * cells floor(o/N) .. floor((o+7)/N), in at most 2 blocks */
    size_t cap = 0, ncand = 0;
    int32_t *cand = NULL;
    hv_status s = HV_OK;
    for (size_t l = 0; l < md->nleaves && s == HV_OK; ++l) {
        if (!any_bit(md->occ + 8 * l)) continue;
        const int32_t *o = orig + 3 * l;
        int32_t a[3], z[3];
        for (int q = 0; q < 3; ++q) {
            a[q] = floor_div(o[q], n) & ~7;
            z[q] = floor_div(o[q] + 7, n) & ~7;
        }
        for (int32_t x = a[0]; x <= z[0] && s == HV_OK; x += 8)
            for (int32_t y = a[1]; y <= z[1] && s == HV_OK; y += 8)
                for (int32_t w = a[2]; w <= z[2] && s == HV_OK; w += 8) {
                    s = hv_grow((void **)&cand, &cap, 3 * (ncand + 1), sizeof *cand);
                    if (s != HV_OK) break;
                    cand[3 * ncand] = x;
                    cand[3 * ncand + 1] = y;
                    cand[3 * ncand + 2] = w;
                    ++ncand;
                }
    }
    if (s != HV_OK) {
        free(cand);
        return s;
    }
    h->ncl = sort_unique(cand, ncand);
    h->cl_origin = cand;
    h->cl_mask = hv_calloc(h->ncl ? h->ncl * 8 : 1, sizeof(uint64_t));
    h->cl_base = hv_calloc(h->ncl + 1, sizeof(uint64_t));
    if (!h->cl_mask || !h->cl_base) return HV_ERR_NOMEM;
    s = hash_build(h->cl_origin, h->ncl, &h->clh, &h->clh_cap);
    if (s != HV_OK) return s;
    plan_ctx c = {h, md, hv_calloc(h->ncl ? 512 * h->ncl : 1, sizeof(int64_t))};
    if (!c.count) return HV_ERR_NOMEM;
    s = hv_parallel_for(md->nleaves, 64, count_range, &c, progress, "export cells");
    if (s == HV_OK) s = hv_parallel_for(h->ncl, 64, cells_range, &c, NULL, "export cells");
    free(c.count);
    if (s != HV_OK) return s;
    for (size_t L = 0; L < h->ncl; ++L) {
        h->cl_base[L] = h->ncells;
        for (int q = 0; q < 8; ++q) h->ncells += (uint64_t)__builtin_popcountll(h->cl_mask[8 * L + q]);
    }
    h->cl_base[h->ncl] = h->ncells;

    /* corner blocks: a block's cells have corners in it and its +8 neighbours */
    size_t nk = 0;
    int32_t *kc = NULL;
    cap = 0;
    for (size_t L = 0; L < h->ncl && s == HV_OK; ++L) {
        if (!any_bit(h->cl_mask + 8 * L)) continue;
        s = hv_grow((void **)&kc, &cap, 3 * (nk + 8), sizeof *kc);
        for (int d = 0; d < 8 && s == HV_OK; ++d) {
            kc[3 * nk] = h->cl_origin[3 * L] + 8 * ((d >> 2) & 1);
            kc[3 * nk + 1] = h->cl_origin[3 * L + 1] + 8 * ((d >> 1) & 1);
            kc[3 * nk + 2] = h->cl_origin[3 * L + 2] + 8 * (d & 1);
            ++nk;
        }
    }
    if (s != HV_OK) {
        free(kc);
        return s;
    }
    h->nkl = sort_unique(kc, nk);
    h->kl_origin = kc;
    h->kl_mask = hv_calloc(h->nkl ? h->nkl * 8 : 1, sizeof(uint64_t));
    h->kl_base = hv_calloc(h->nkl + 1, sizeof(uint64_t));
    h->kl_prefix = hv_calloc(h->nkl ? h->nkl * 8 : 1, sizeof(uint16_t));
    if (!h->kl_mask || !h->kl_base || !h->kl_prefix) return HV_ERR_NOMEM;
    s = hash_build(h->kl_origin, h->nkl, &h->klh, &h->klh_cap);
    if (s != HV_OK) return s;
    s = hv_parallel_for(h->nkl, 8, corners_range, &c, progress, "export points");
    if (s != HV_OK) return s;
    for (size_t K = 0; K < h->nkl; ++K) {
        h->kl_base[K] = h->npoints;
        uint16_t run = 0;
        for (int q = 0; q < 8; ++q) {
            h->kl_prefix[8 * K + q] = run;
            run = (uint16_t)(run + __builtin_popcountll(h->kl_mask[8 * K + q]));
        }
        h->npoints += run;
    }
    h->kl_base[h->nkl] = h->npoints;
    return HV_OK;
}

int ex_hexmesh_ids64(const ex_hexmesh *h)
{
    return h->npoints > (uint64_t)INT32_MAX || h->ncells > (uint64_t)(INT32_MAX / 8);
}

/* ---- fill ------------------------------------------------------------------------------- */

typedef struct fill_ctx {
    const ex_hexmesh *h;
    const ex_model *md;
    float *points;
    int32_t *conn32; /* one of these, by the id width */
    int64_t *conn64;
    float *occupancy;
    float *const *frac;
    float *const *props;
} fill_ctx;

static hv_status points_range(void *ctx, size_t b, size_t e, int thread)
{
    (void)thread;
    const fill_ctx *c = ctx;
    const ex_hexmesh *h = c->h;
    hv_transform xf = hv_volume_get_transform(c->md->vol);
    for (size_t K = b; K < e; ++K) {
        const int32_t *o = h->kl_origin + 3 * K;
        uint64_t id = h->kl_base[K];
        for (unsigned q = 0; q < 8; ++q)
            for (uint64_t bits = h->kl_mask[8 * K + q]; bits; bits &= bits - 1) {
                unsigned n = q * 64 + (unsigned)__builtin_ctzll(bits);
                int32_t p[3] = {o[0] + (int32_t)(n >> 6), o[1] + (int32_t)((n >> 3) & 7),
                                o[2] + (int32_t)(n & 7)};
                /* corner p of the coarse lattice sits on the low face of voxel p*N */
                for (int a = 0; a < 3; ++a)
                    c->points[3 * id + a] = (float)(xf.origin[a] +
                                                    ((double)p[a] * h->n - 0.5) * xf.voxel[a]);
                ++id;
            }
    }
    return HV_OK;
}

/* VTK_HEXAHEDRON vertex order: the z-low face counter-clockwise seen from +z, then z-high. */
static const int HEX[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                              {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};

static hv_status cells_fill_range(void *ctx, size_t b, size_t e, int thread)
{
    (void)thread;
    const fill_ctx *c = ctx;
    const ex_hexmesh *h = c->h;
    const ex_model *md = c->md;
    int n = h->n, m = md->m;
    double inv_cell = 1.0 / ((double)n * n * n);
    hv_accessor acc;
    hv_accessor_init(&acc, md->vol);
    double p[HV_MAX_MATERIALS], sum[HV_MAX_MATERIALS];
    for (size_t L = b; L < e; ++L) {
        const int32_t *o = h->cl_origin + 3 * L;
        const uint64_t *w = h->cl_mask + 8 * L;
        if (!any_bit(w)) continue;
        int64_t K[8];
        for (int d = 0; d < 8; ++d) {
            K[d] = hash_find(h->kl_origin, h->klh, h->klh_cap, o[0] + 8 * ((d >> 2) & 1),
                             o[1] + 8 * ((d >> 1) & 1), o[2] + 8 * (d & 1));
            if (K[d] < 0) return hv_error_set(HV_ERR_INTERNAL, "export: corner block missing");
        }
        uint64_t id = h->cl_base[L];
        for (unsigned q = 0; q < 8; ++q)
            for (uint64_t bits = w[q]; bits; bits &= bits - 1) {
                unsigned cn = q * 64 + (unsigned)__builtin_ctzll(bits);
                int x = (int)(cn >> 6), y = (int)((cn >> 3) & 7), z = (int)(cn & 7);
                for (int v = 0; v < 8; ++v) {
                    int px = x + HEX[v][0], py = y + HEX[v][1], pz = z + HEX[v][2];
                    int d = ((px >> 3) << 2) | ((py >> 3) << 1) | (pz >> 3);
                    unsigned off = HV_LEAF_OFFSET(px, py, pz);
                    const uint64_t *km = h->kl_mask + 8 * K[d];
                    uint64_t below = km[off >> 6] & ((1ull << (off & 63)) - 1);
                    uint64_t pid = h->kl_base[K[d]] + h->kl_prefix[8 * K[d] + (off >> 6)] +
                                   (uint64_t)__builtin_popcountll(below);
                    if (c->conn64) c->conn64[8 * id + (uint64_t)v] = (int64_t)pid;
                    else c->conn32[8 * id + (uint64_t)v] = (int32_t)pid;
                }
                /* average the fractions of the cell's occupied voxels */
                int count = 0;
                for (int j = 0; j < m; ++j) sum[j] = 0;
                double gsum[EX_MAX_ARRAYS];
                for (int g = 0; md->ngrids && g < md->nprops; ++g) gsum[g] = 0;
                int32_t x0 = (o[0] + x) * n, y0 = (o[1] + y) * n, z0 = (o[2] + z) * n;
                /* by voxel leaves: an absent or empty leaf is skipped whole */
                for (int32_t bx = x0 & ~7; bx < x0 + n; bx += 8)
                    for (int32_t by = y0 & ~7; by < y0 + n; by += 8)
                        for (int32_t bz = z0 & ~7; bz < z0 + n; bz += 8) {
                            int64_t l = hv_accessor_leaf(&acc, bx, by, bz);
                            if (l < 0 || !any_bit(md->occ + 8 * l)) continue;
                            const uint64_t *lw = md->occ + 8 * l;
                            for (int qq = 0; qq < 8; ++qq)
                                for (uint64_t u = lw[qq]; u; u &= u - 1) {
                                    unsigned off = (unsigned)(64 * qq + __builtin_ctzll(u));
                                    int32_t i = bx + (int32_t)(off >> 6), jj = by + (int32_t)((off >> 3) & 7),
                                            k = bz + (int32_t)(off & 7);
                                    if (i < x0 || i >= x0 + n || jj < y0 || jj >= y0 + n || k < z0 || k >= z0 + n)
                                        continue;
                                    ++count;
                                    if (md->ngrids) ex_grid_add(md, (size_t)l, off, gsum);
                                    if (!m) continue;
                                    for (int j = 0; j < m; ++j)
                                        p[j] = hv_volume_leaf_float_c(md->vol, md->grids[j], (size_t)l)[off];
                                    hv_status s = ex_check_fractions(md, p, i, jj, k);
                                    if (s != HV_OK) return s;
                                    for (int j = 0; j < m; ++j) sum[j] += p[j];
                                }
                        }
                c->occupancy[id] = (float)(count * inv_cell);
                if (count > 0 && md->ngrids) {
                    for (int g = 0; g < md->nprops; ++g) gsum[g] /= count;
                    ex_grid_values(md, gsum, c->props, (size_t)id);
                }
                if (m && count > 0) {
                    for (int j = 0; j < m; ++j) {
                        p[j] = sum[j] / count;
                        c->frac[j][id] = (float)p[j];
                    }
                    ex_eval_props(md, p, c->props, (size_t)id);
                }
                ++id;
            }
    }
    return HV_OK;
}

hv_status ex_hexmesh_fill(const ex_hexmesh *h, const ex_model *md, float *points, void *conn,
                          int conn64, float *occupancy, float *const *fractions,
                          float *const *props, const hv_progress *progress)
{
    fill_ctx c = {h, md, points, conn64 ? NULL : conn, conn64 ? conn : NULL, occupancy, fractions,
                  props};
    hv_status s = hv_parallel_for(h->nkl, 16, points_range, &c, progress, "export points");
    if (s != HV_OK) return s;
    return hv_parallel_for(h->ncl, 8, cells_fill_range, &c, progress, "export fill");
}
