/* src/mesh/mesh.c - mesh construction: exact vertex welding (parallel, deterministic: vertices
 * numbered by first appearance), edge adjacency through per-vertex buckets, and the report
 * (volume, area, shells, open/non-manifold edges, degenerate and flipped facets). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "mesh_internal.h"

#define CHUNK 65536

/* ---- welding ---------------------------------------------------------------------------- */

static inline uint32_t fbits(float f)
{
    if (f == 0.0f) f = 0.0f; /* -0 welds with +0 */
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static inline uint64_t hash_xyz(const float *p)
{
    uint64_t h = fbits(p[0]) * 0x9E3779B97F4A7C15ull;
    h = (h ^ (h >> 31)) + fbits(p[1]) * 0xC2B2AE3D27D4EB4Full;
    h = (h ^ (h >> 29)) + fbits(p[2]) * 0x165667B19E3779F9ull;
    return h ^ (h >> 32);
}

static inline int same_xyz(const float *a, const float *b)
{
    return fbits(a[0]) == fbits(b[0]) && fbits(a[1]) == fbits(b[1]) && fbits(a[2]) == fbits(b[2]);
}

typedef struct weld_ctx {
    const float *pts; /* 3 floats per point: a soup's corners, or an indexed mesh's points */
    size_t nrefs;
    uint64_t *hash;
    uint32_t *rep; /* first ref with the same position */
    int parts_log2;
} weld_ctx;

static hv_status weld_hash(void *c, size_t b, size_t e, int t)
{
    (void)t;
    weld_ctx *w = c;
    for (size_t r = b; r < e; ++r) w->hash[r] = hash_xyz(w->pts + 3 * r);
    return HV_OK;
}

/* Partition `part` (by the hash's top bits) finds, for each of its refs, the first ref at
 * the same position. Refs are scanned in order, so the first inserted is the minimum. */
static hv_status weld_part(void *c, size_t b, size_t e, int t)
{
    (void)t;
    weld_ctx *w = c;
    int shift = 64 - w->parts_log2;
    for (size_t part = b; part < e; ++part) {
        size_t count = 0;
        for (size_t r = 0; r < w->nrefs; ++r)
            if ((size_t)(w->parts_log2 ? w->hash[r] >> shift : 0) == part) ++count;
        size_t cap = 16;
        while (cap < 2 * count) cap *= 2;
        uint32_t *table = hv_malloc_array(cap, sizeof(uint32_t));
        if (!table) return HV_ERR_NOMEM;
        memset(table, 0xFF, cap * sizeof(uint32_t));
        for (size_t r = 0; r < w->nrefs; ++r) {
            uint64_t h = w->hash[r];
            if ((size_t)(w->parts_log2 ? h >> shift : 0) != part) continue;
            const float *p = w->pts + 3 * r;
            for (size_t i = (size_t)h & (cap - 1);; i = (i + 1) & (cap - 1)) {
                uint32_t s = table[i];
                if (s == UINT32_MAX) {
                    table[i] = (uint32_t)r;
                    w->rep[r] = (uint32_t)r;
                    break;
                }
                if (w->hash[s] == h && same_xyz(w->pts + 3 * (size_t)s, p)) {
                    w->rep[r] = s;
                    break;
                }
            }
        }
        free(table);
    }
    return HV_OK;
}

/* ---- adjacency -------------------------------------------------------------------------- */

typedef struct adj_ctx {
    hv_mesh *m;
    const uint32_t *start; /* per vertex: first half-edge slot of its bucket */
    uint32_t *half; /* half-edges (3f+e) bucketed by lower vertex; sorted by upper vertex here */
    uint64_t *open, *nonmanifold, *conflict; /* per chunk counters */
} adj_ctx;

static inline uint32_t he_from(const hv_mesh *m, uint32_t h) { return m->tri[h]; }
static inline uint32_t he_to(const hv_mesh *m, uint32_t h)
{
    return m->tri[h - h % 3 + (h % 3 + 1) % 3];
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* Pair the half-edges of one undirected edge: g[0..k-1], sorted by half-edge index. */
static void pair_group(hv_mesh *m, const uint32_t *g, size_t k, uint64_t *open, uint64_t *nm,
                       uint64_t *conflict)
{
    if (k == 1) {
        m->nbr[g[0]] = HV_MESH_OPEN;
        ++*open;
        return;
    }
    if (k == 2) {
        m->nbr[g[0]] = (int32_t)(g[1] / 3);
        m->nbr[g[1]] = (int32_t)(g[0] / 3);
        if (he_from(m, g[0]) == he_from(m, g[1])) ++*conflict;
        return;
    }
    ++*nm;
    /* non-manifold: pair each half-edge, in order, with the next unpaired one of opposite
     * direction, falling back to the next unpaired one of its own direction; a last odd one
     * stays open. The half-edges of one edge run in two directions, so two queues of the unpaired
     * ones, in order, find each partner in amortised constant time: linear in k (a million
     * facets on one edge are paired in milliseconds, not minutes). */
    uint32_t small[3 * 64];
    uint32_t *buf = k <= 64 ? small : hv_malloc_array(k, 3 * sizeof *buf);
    if (!buf) { /* degrade: leave all open */
        for (size_t i = 0; i < k; ++i) m->nbr[g[i]] = HV_MESH_OPEN;
        return;
    }
    uint32_t *queue[2] = {buf, buf + k}, *used = buf + 2 * k;
    size_t len[2] = {0, 0}, head[2] = {0, 0};
    const uint32_t first = he_from(m, g[0]);
    for (size_t i = 0; i < k; ++i) {
        int d = he_from(m, g[i]) != first;
        queue[d][len[d]++] = (uint32_t)i;
        used[i] = 0;
        m->eflags[g[i] / 3] = (uint8_t)(m->eflags[g[i] / 3] | (1u << (g[i] % 3)));
    }
    for (size_t i = 0; i < k; ++i) {
        if (used[i]) continue;
        used[i] = 1; /* every half-edge before the next i is used: a queue's head is the next one */
        int d = he_from(m, g[i]) != first;
        size_t pick = k;
        for (int pass = 0; pass < 2 && pick == k; ++pass) {
            int q = pass == 0 ? !d : d;
            while (head[q] < len[q] && used[queue[q][head[q]]]) ++head[q];
            if (head[q] < len[q]) pick = queue[q][head[q]];
        }
        if (pick == k) {
            m->nbr[g[i]] = HV_MESH_OPEN;
            continue;
        }
        used[pick] = 1;
        m->nbr[g[i]] = (int32_t)(g[pick] / 3);
        m->nbr[g[pick]] = (int32_t)(g[i] / 3);
    }
    if (buf != small) free(buf);
}

static hv_status adj_range(void *c, size_t b, size_t e, int t)
{
    (void)t;
    adj_ctx *a = c;
    hv_mesh *m = a->m;
    size_t chunk = b / CHUNK;
    uint64_t open = 0, nm = 0, conflict = 0;
    uint64_t small[64];
    for (size_t v = b; v < e; ++v) {
        size_t s = a->start[v], k = a->start[v + 1] - s;
        if (k == 0) continue;
        /* sort the bucket by (upper vertex, half-edge index): groups come out contiguous and
         * in a deterministic order */
        uint64_t *keys = k <= 64 ? small : malloc(k * sizeof *keys);
        if (!keys) return hv_error_set(HV_ERR_NOMEM, "out of memory building edge adjacency");
        for (size_t i = 0; i < k; ++i) {
            uint32_t h = a->half[s + i];
            uint32_t hi = HV_MAX(he_from(m, h), he_to(m, h));
            keys[i] = ((uint64_t)hi << 32) | h;
        }
        if (k <= 16) { /* insertion sort: buckets are tiny */
            for (size_t i = 1; i < k; ++i) {
                uint64_t x = keys[i];
                size_t j = i;
                for (; j > 0 && keys[j - 1] > x; --j) keys[j] = keys[j - 1];
                keys[j] = x;
            }
        } else {
            qsort(keys, k, sizeof *keys, cmp_u64);
        }
        for (size_t i = 0; i < k; ++i) a->half[s + i] = (uint32_t)keys[i];
        uint32_t gsmall[64];
        for (size_t i = 0; i < k;) {
            size_t j = i;
            while (j < k && (keys[j] >> 32) == (keys[i] >> 32)) ++j;
            size_t n = j - i;
            uint32_t *g = n <= 64 ? gsmall : malloc(n * sizeof *g);
            if (!g) {
                if (keys != small) free(keys);
                return hv_error_set(HV_ERR_NOMEM, "out of memory building edge adjacency");
            }
            for (size_t q = 0; q < n; ++q) g[q] = (uint32_t)keys[i + q];
            pair_group(m, g, n, &open, &nm, &conflict);
            if (g != gsmall) free(g);
            i = j;
        }
        if (keys != small) free(keys);
    }
    a->open[chunk] = open;
    a->nonmanifold[chunk] = nm;
    a->conflict[chunk] = conflict;
    return HV_OK;
}

/* ---- per-facet geometry ----------------------------------------------------------------- */

typedef struct geo_ctx {
    const hv_mesh *m;
    const float *normals;
    double center[3];
    double *vol, *area;         /* per chunk */
    uint64_t *degen, *mismatch; /* per chunk */
} geo_ctx;

static hv_status geo_range(void *c, size_t b, size_t e, int t)
{
    (void)t;
    geo_ctx *g = c;
    const hv_mesh *m = g->m;
    double vol = 0, area = 0;
    uint64_t degen = 0, mismatch = 0;
    for (size_t f = b; f < e; ++f) {
        const uint32_t *tv = m->tri + 3 * f;
        double p[3][3];
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) p[k][a] = (double)m->xyz[3 * (size_t)tv[k] + (size_t)a] - g->center[a];
        double u[3], v[3], w[3], cr[3];
        for (int a = 0; a < 3; ++a) {
            u[a] = p[1][a] - p[0][a];
            v[a] = p[2][a] - p[0][a];
            w[a] = p[2][a] - p[1][a];
        }
        cr[0] = u[1] * v[2] - u[2] * v[1];
        cr[1] = u[2] * v[0] - u[0] * v[2];
        cr[2] = u[0] * v[1] - u[1] * v[0];
        double len = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
        double emax = HV_MAX(HV_MAX(u[0] * u[0] + u[1] * u[1] + u[2] * u[2],
                                    v[0] * v[0] + v[1] * v[1] + v[2] * v[2]),
                             w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        /* degenerate: repeated vertex, or height below 1e-10 of the longest edge */
        if (tv[0] == tv[1] || tv[1] == tv[2] || tv[0] == tv[2] || len <= 1e-10 * emax) ++degen;
        area += 0.5 * len;
        vol += (p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
                p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0])) / 6.0;
        if (g->normals) {
            const float *n = g->normals + 3 * f;
            if (n[0] * cr[0] + n[1] * cr[1] + n[2] * cr[2] < 0) ++mismatch;
        }
    }
    size_t chunk = b / CHUNK;
    g->vol[chunk] = vol;
    g->area[chunk] = area;
    g->degen[chunk] = degen;
    g->mismatch[chunk] = mismatch;
    return HV_OK;
}

/* ---- shells and orientation ------------------------------------------------------------ */

static uint32_t uf_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

/* Shells: union-find over shared edges (all facets around an edge, manifold or not).
 * Orientation: BFS over paired edges assigning each facet a parity relative to its shell's
 * seed (flip when the neighbour runs the shared edge the same way); per shell, the smaller
 * parity class counts as flipped. */
static hv_status shells_and_flips(hv_mesh *m, const uint32_t *start, const uint32_t *half)
{
    size_t nf = m->nf;
    uint32_t *parent = hv_malloc_array(nf, sizeof *parent);
    uint32_t *queue = hv_malloc_array(nf, sizeof *queue);
    uint8_t *parity = hv_calloc(nf, 1);
    uint8_t *seen = hv_calloc(nf, 1);
    uint64_t *cnt = NULL;
    if (!parent || !queue || !parity || !seen) {
        free(parent);
        free(queue);
        free(parity);
        free(seen);
        return HV_ERR_NOMEM;
    }
    for (size_t f = 0; f < nf; ++f) parent[f] = (uint32_t)f;
    /* union all facets sharing an undirected edge: within a vertex bucket the half-edges of
     * one edge are contiguous (sorted by upper vertex in adj_range) */
    for (size_t v = 0; v < m->nv; ++v) {
        for (uint32_t i = start[v] + 1; i < start[v + 1]; ++i) {
            uint32_t h = half[i], h0 = half[i - 1];
            if (HV_MAX(he_from(m, h), he_to(m, h)) != HV_MAX(he_from(m, h0), he_to(m, h0)))
                continue;
            uint32_t a = uf_find(parent, h / 3), b = uf_find(parent, h0 / 3);
            if (a != b) parent[a < b ? b : a] = a < b ? a : b;
        }
    }
    uint64_t shells = 0;
    for (size_t f = 0; f < nf; ++f)
        if (uf_find(parent, (uint32_t)f) == f) ++shells;
    /* parity BFS */
    cnt = hv_calloc(nf, 2 * sizeof(uint64_t)); /* per root: class counts */
    if (!cnt) {
        free(parent);
        free(queue);
        free(parity);
        free(seen);
        return HV_ERR_NOMEM;
    }
    for (size_t s = 0; s < nf; ++s) {
        if (seen[s]) continue;
        size_t qh = 0, qt = 0;
        queue[qt++] = (uint32_t)s;
        seen[s] = 1;
        while (qh < qt) {
            uint32_t f = queue[qh++];
            cnt[2 * (size_t)uf_find(parent, f) + parity[f]]++;
            for (int e = 0; e < 3; ++e) {
                int32_t g = m->nbr[3 * (size_t)f + (size_t)e];
                if (g < 0 || seen[g]) continue;
                /* the edge f runs a->b; a consistent neighbour runs b->a */
                uint32_t a = m->tri[3 * f + (uint32_t)e];
                int same = 0;
                for (int k = 0; k < 3; ++k)
                    if (m->tri[3 * (size_t)g + (size_t)k] == a &&
                        m->tri[3 * (size_t)g + (size_t)(k + 1) % 3] == m->tri[3 * f + (uint32_t)(e + 1) % 3])
                        same = 1;
                parity[g] = (uint8_t)(parity[f] ^ same);
                seen[g] = 1;
                queue[qt++] = (uint32_t)g;
            }
        }
    }
    uint64_t flipped = 0;
    for (size_t f = 0; f < nf; ++f)
        if (parent[f] == f) flipped += HV_MIN(cnt[2 * f], cnt[2 * f + 1]);
    m->report.shells = shells;
    m->report.flipped_facets = flipped;
    free(cnt);
    free(parent);
    free(queue);
    free(parity);
    free(seen);
    return HV_OK;
}

/* ---- build ------------------------------------------------------------------------------ */

static hv_status build_topology(hv_mesh *m, const float *normals)
{
    size_t nf = m->nf, nv = m->nv;
    hv_status s = HV_OK;
    uint32_t *start = hv_calloc(nv + 1, sizeof *start);
    uint32_t *half = hv_malloc_array(3 * nf, sizeof *half);
    size_t nchunks = nv / CHUNK + 1, fchunks = nf / CHUNK + 1;
    uint64_t *cnts = hv_calloc(3 * nchunks + 2 * fchunks, sizeof *cnts);
    double *sums = hv_calloc(2 * fchunks, sizeof *sums);
    m->nbr = hv_malloc_array(3 * nf, sizeof *m->nbr);
    m->eflags = hv_calloc(nf, 1);
    if (!start || !half || !cnts || !sums || !m->nbr || !m->eflags) {
        s = HV_ERR_NOMEM;
        goto done;
    }
    /* bucket half-edges by their lower vertex (counting sort, stable in half-edge order) */
    for (size_t h = 0; h < 3 * nf; ++h) {
        uint32_t a = he_from(m, (uint32_t)h), b = he_to(m, (uint32_t)h);
        if (a != b) start[HV_MIN(a, b) + 1]++;
    }
    for (size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
    {
        uint32_t *fill = hv_malloc_array(nv + 1, sizeof *fill);
        if (!fill) {
            s = HV_ERR_NOMEM;
            goto done;
        }
        memcpy(fill, start, (nv + 1) * sizeof *fill);
        for (size_t h = 0; h < 3 * nf; ++h) {
            uint32_t a = he_from(m, (uint32_t)h), b = he_to(m, (uint32_t)h);
            if (a != b) half[fill[HV_MIN(a, b)]++] = (uint32_t)h;
            else m->nbr[h] = HV_MESH_OPEN; /* collapsed edge of a degenerate facet */
        }
        free(fill);
    }
    adj_ctx actx = {m, start, half, cnts, cnts + nchunks, cnts + 2 * nchunks};
    s = hv_parallel_for(nv, CHUNK, adj_range, &actx, NULL, "adjacency");
    if (s != HV_OK) goto done;
    for (size_t c = 0; c < nchunks; ++c) {
        m->report.open_edges += actx.open[c];
        m->report.nonmanifold_edges += actx.nonmanifold[c];
    }

    /* geometry */
    hv_mesh_report *r = &m->report;
    for (int a = 0; a < 3; ++a) {
        r->bbox_min[a] = INFINITY;
        r->bbox_max[a] = -INFINITY;
    }
    for (size_t v = 0; v < nv; ++v)
        for (int a = 0; a < 3; ++a) {
            double x = m->xyz[3 * v + (size_t)a];
            if (x < r->bbox_min[a]) r->bbox_min[a] = x;
            if (x > r->bbox_max[a]) r->bbox_max[a] = x;
        }
    geo_ctx g = {m, normals, {0, 0, 0}, sums, sums + fchunks, cnts + 3 * nchunks,
                 cnts + 3 * nchunks + fchunks};
    for (int a = 0; a < 3; ++a) g.center[a] = 0.5 * (r->bbox_min[a] + r->bbox_max[a]);
    s = hv_parallel_for(nf, CHUNK, geo_range, &g, NULL, "report");
    if (s != HV_OK) goto done;
    for (size_t c = 0; c < fchunks; ++c) { /* fixed order: same bits for any thread count */
        r->volume += g.vol[c];
        r->area += g.area[c];
        r->degenerate_facets += g.degen[c];
        r->normal_mismatch += g.mismatch[c];
    }
    s = shells_and_flips(m, start, half);
done:
    free(start);
    free(half);
    free(cnts);
    free(sums);
    return s;
}

/* A new mesh of nf facets, its tri array allocated (filled by the caller). */
static hv_status mesh_new(size_t nf, const char *name, hv_mesh_format format, hv_mesh **out)
{
    *out = NULL;
    if (nf == 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: contains no facets", name);
    if (nf > (size_t)INT32_MAX / 3)
        return hv_error_set(HV_ERR_LIMIT, "%s: %zu facets exceed the limit of %d", name, nf,
                            INT32_MAX / 3);
    hv_mesh *m = hv_calloc(1, sizeof *m);
    if (!m) return HV_ERR_NOMEM;
    m->name = hv_strdup(name);
    m->nf = nf;
    m->report.format = format;
    m->report.facets = nf;
    m->tri = hv_malloc_array(3 * nf, sizeof *m->tri);
    if (!m->name || !m->tri) {
        hv_mesh_destroy(m);
        return HV_ERR_NOMEM;
    }
    *out = m;
    return HV_OK;
}

/* w->rep[i]: the first of the w->nrefs points at the same position as point i (w->hash is
 * scratch of the same length, free for the caller's use afterwards). */
static hv_status weld(weld_ctx *w)
{
    hv_status s = hv_parallel_for(w->nrefs, CHUNK, weld_hash, w, NULL, "weld");
    if (s != HV_OK) return s;
    /* one partition per thread and a few more for balance; a single one when small */
    int threads = hv_threads();
    w->parts_log2 = w->nrefs < 200000 || threads == 1 ? 0 : 3;
    while ((1 << w->parts_log2) < 2 * threads && w->parts_log2 > 0 && w->parts_log2 < 6)
        ++w->parts_log2;
    return hv_parallel_for((size_t)1 << w->parts_log2, 1, weld_part, w, NULL, "weld");
}

/* Adjacency, the report and the default body of a mesh whose vertices and facets are set. */
static hv_status finish(hv_mesh *m, const float *normals, hv_mesh **out)
{
    hv_status s = build_topology(m, normals);
    if (s == HV_OK) s = hv_mesh_default_body(m);
    if (s != HV_OK) {
        hv_mesh_destroy(m);
        return s;
    }
    *out = m;
    return HV_OK;
}

hv_status hv_mesh_from_soup(const float *soup, const float *normals, size_t nf, const char *name,
                            hv_mesh_format format, hv_mesh **out)
{
    hv_mesh *m;
    hv_status s = mesh_new(nf, name, format, &m);
    if (s != HV_OK) return s;
    size_t nrefs = 3 * nf;
    weld_ctx w = {soup, nrefs, hv_malloc_array(nrefs, sizeof(uint64_t)),
                  hv_malloc_array(nrefs, sizeof(uint32_t)), 0};
    if (!w.hash || !w.rep) s = HV_ERR_NOMEM;
    if (s == HV_OK) s = weld(&w);
    if (s != HV_OK) goto fail;
    /* number vertices by first appearance; reuse hash[] as the ref -> vertex map */
    size_t nv = 0;
    for (size_t r = 0; r < nrefs; ++r) {
        if (w.rep[r] == r) w.hash[r] = nv++;
        m->tri[r] = (uint32_t)w.hash[w.rep[r]];
    }
    m->nv = nv;
    m->report.vertices = nv;
    m->xyz = hv_malloc_array(3 * nv, sizeof *m->xyz);
    if (!m->xyz) {
        s = HV_ERR_NOMEM;
        goto fail;
    }
    for (size_t r = 0; r < nrefs; ++r)
        if (w.rep[r] == r) memcpy(m->xyz + 3 * w.hash[r], soup + 3 * r, 3 * sizeof(float));
    free(w.hash);
    free(w.rep);
    return finish(m, normals, out);
fail:
    free(w.hash);
    free(w.rep);
    hv_mesh_destroy(m);
    return s;
}

/* The mesh hv_mesh_from_soup makes of the soup these facets expand to, welding the npts points
 * (3MF, issue 26 item 2: a million-facet mesh has half a million points, not three million
 * corners): vertices are the points welded, numbered by the first corner that uses them, each
 * with that corner's coordinates (-0 and +0 weld; the first one's sign is kept, as there). */
hv_status hv_mesh_from_indexed(const float *xyz, size_t npts, const uint32_t *tri, size_t nf,
                               const char *name, hv_mesh_format format, hv_mesh **out)
{
    hv_mesh *m;
    hv_status s = mesh_new(nf, name, format, &m);
    if (s != HV_OK) return s;
    size_t nrefs = 3 * nf;
    weld_ctx w = {xyz, npts, hv_malloc_big(HV_MAX(npts, 1), sizeof(uint64_t)),
                  hv_malloc_big(HV_MAX(npts, 1), sizeof(uint32_t)), 0};
    m->xyz = hv_malloc_array(3 * HV_MIN(npts, nrefs), sizeof *m->xyz);
    if (!w.hash || !w.rep || !m->xyz) s = HV_ERR_NOMEM;
    if (s == HV_OK) s = weld(&w);
    if (s != HV_OK) goto fail;
    /* hash[] becomes the point -> vertex map */
    memset(w.hash, 0xFF, npts * sizeof *w.hash);
    size_t nv = 0;
    for (size_t r = 0; r < nrefs; ++r) {
        uint32_t p = tri[r], g = w.rep[p];
        if (w.hash[g] == UINT64_MAX) {
            memcpy(m->xyz + 3 * nv, xyz + 3 * (size_t)p, 3 * sizeof(float));
            w.hash[g] = nv++;
        }
        m->tri[r] = (uint32_t)w.hash[g];
    }
    m->nv = nv;
    m->report.vertices = nv;
    float *fit = nv < HV_MIN(npts, nrefs) ? realloc(m->xyz, 3 * nv * sizeof *m->xyz) : NULL;
    if (fit) m->xyz = fit;
    free(w.hash);
    free(w.rep);
    return finish(m, NULL, out);
fail:
    free(w.hash);
    free(w.rep);
    hv_mesh_destroy(m);
    return s;
}

hv_status hv_mesh_create(const float *xyz, size_t nvert, const uint32_t *facets, size_t nf,
                         hv_mesh **out)
{
    *out = NULL;
    if (nf == 0) return hv_error_set(HV_ERR_INVALID, "mesh has no facets");
    for (size_t v = 0; v < 3 * nvert; ++v)
        if (!isfinite(xyz[v]))
            return hv_error_set(HV_ERR_INVALID, "vertex %zu has a non-finite coordinate (%g)",
                                v / 3, (double)xyz[v]);
    for (size_t r = 0; r < 3 * nf; ++r)
        if (facets[r] >= nvert)
            return hv_error_set(HV_ERR_INVALID, "facet %zu: vertex index %u out of range (%zu vertices)", r / 3,
                                facets[r], nvert);
    /* the mesh the expanded soup would weld to, welding the points, not the corners */
    return hv_mesh_from_indexed(xyz, nvert, facets, nf, "", HV_MESH_GENERATED, out);
}

void hv_mesh_destroy(hv_mesh *m)
{
    if (!m) return;
    free(m->name);
    free(m->xyz);
    free(m->tri);
    free(m->nbr);
    free(m->eflags);
    hv_mesh_bodies_free(m);
    hv_mesh_appearance_free(m);
    for (size_t i = 0; i < m->nnotes; ++i) free(m->notes[i]);
    free(m->notes);
    for (size_t i = 0; i < m->nitems; ++i) free((char *)m->items[i].object_name);
    free(m->items);
    free(m->file_unit);
    free(m);
}

hv_status hv_mesh_set_file_info(hv_mesh *m, const char *unit, const hv_mesh_item *items, size_t n)
{
    if (unit && !(m->file_unit = hv_strdup(unit))) return HV_ERR_NOMEM;
    if (n == 0) return HV_OK;
    if (!(m->items = hv_calloc(n, sizeof *m->items))) return HV_ERR_NOMEM;
    for (size_t i = 0; i < n; ++i) {
        m->items[i] = items[i];
        m->items[i].object_name = hv_strdup(items[i].object_name ? items[i].object_name : "");
        if (!m->items[i].object_name) return HV_ERR_NOMEM; /* the names before it are freed with the mesh */
        m->nitems = i + 1;
    }
    return HV_OK;
}

const char *hv_mesh_file_unit(const hv_mesh *m) { return m->file_unit; }
size_t hv_mesh_item_count(const hv_mesh *m) { return m->nitems; }
const hv_mesh_item *hv_mesh_item_at(const hv_mesh *m, size_t i) { return i < m->nitems ? &m->items[i] : NULL; }

hv_status hv_mesh_add_note(hv_mesh *m, const char *text)
{
    char *copy = hv_strdup(text);
    char **n = copy ? hv_realloc(m->notes, (m->nnotes + 1) * sizeof *n) : NULL;
    if (!n) {
        free(copy);
        return HV_ERR_NOMEM;
    }
    m->notes = n;
    m->notes[m->nnotes++] = copy;
    return HV_OK;
}

size_t hv_mesh_note_count(const hv_mesh *m) { return m->nnotes; }
const char *hv_mesh_note_at(const hv_mesh *m, size_t i) { return i < m->nnotes ? m->notes[i] : ""; }

size_t hv_mesh_vertex_count(const hv_mesh *m) { return m->nv; }
size_t hv_mesh_facet_count(const hv_mesh *m) { return m->nf; }
const float *hv_mesh_vertices(const hv_mesh *m) { return m->xyz; }
const uint32_t *hv_mesh_facets(const hv_mesh *m) { return m->tri; }
const int32_t *hv_mesh_neighbors(const hv_mesh *m) { return m->nbr; }
const uint8_t *hv_mesh_edge_flags(const hv_mesh *m) { return m->eflags; }
const hv_mesh_report *hv_mesh_get_report(const hv_mesh *m) { return &m->report; }
const char *hv_mesh_name(const hv_mesh *m) { return m->name ? m->name : ""; }
