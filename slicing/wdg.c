/* slicing/wdg.c - the weighted directed graph of Wu 2.4.1 (facets as nodes, shared edges as
 * arcs weighted by the sum of the edge's local vertex subscripts) and the z-sorted facet
 * index that lets each plane touch only the facets crossing it. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "slice_internal.h"

#define GRAIN 8192

/* Mesh local edge e (0: v0v1, 1: v1v2, 2: v2v0) -> Wu weight (v0v1 -> 1, v1v2 -> 3,
 * v2v0 -> 2). */
static const int k_weight_of_edge[3] = {1, 3, 2};

typedef struct build_ctx {
    hv_slicer *s;
    const uint32_t *tri;
    const int32_t *nbr;
    uint8_t *ambiguous; /* per facet: some edge needs the sequential pass */
} build_ctx;

/* The local edges of facet g with the vertex set {a, b} whose neighbour is f. */
static int matching_edges(const uint32_t *tri, const int32_t *nbr, uint32_t g, uint32_t f,
                          uint32_t a, uint32_t b, int out[3])
{
    int k = 0;
    for (int e = 0; e < 3; ++e) {
        uint32_t c = tri[3 * g + e], d = tri[3 * g + (e + 1) % 3];
        if (((c == a && d == b) || (c == b && d == a)) && nbr[3 * g + e] == (int32_t)f)
            out[k++] = e;
    }
    return k;
}

static inline void set_arc(hv_slicer *s, uint32_t f, int w, int32_t g, int wg)
{
    s->arc[3 * (size_t)f + (size_t)(w - 1)] = g;
    uint8_t mask = (uint8_t)(3u << (2 * (w - 1)));
    s->back[f] = (uint8_t)((s->back[f] & ~mask) | (uint8_t)(wg << (2 * (w - 1))));
}

/* Arcs of facets [b, e): the twin of half-edge (f, e) is the edge of the neighbour g with the
 * same two vertices that points back to f. More than one candidate only happens between
 * degenerate facets with a repeated edge; those facets are resolved sequentially. */
static hv_status arcs_range(void *c, size_t b, size_t e, int t)
{
    (void)t;
    build_ctx *x = c;
    hv_slicer *s = x->s;
    for (size_t f = b; f < e; ++f) {
        s->back[f] = 0;
        for (int le = 0; le < 3; ++le) {
            int w = k_weight_of_edge[le];
            int32_t g = x->nbr[3 * f + (size_t)le];
            if (g < 0) {
                set_arc(s, (uint32_t)f, w, -1, 0);
                continue;
            }
            uint32_t va = x->tri[3 * f + (size_t)le], vb = x->tri[3 * f + (size_t)(le + 1) % 3];
            int cand[3];
            int k = matching_edges(x->tri, x->nbr, (uint32_t)g, (uint32_t)f, va, vb, cand);
            if (k == 1 && (uint32_t)g != f) {
                set_arc(s, (uint32_t)f, w, g, k_weight_of_edge[cand[0]]);
            } else {
                set_arc(s, (uint32_t)f, w, -1, 0);
                if (k != 0) x->ambiguous[f] = 1;
            }
        }
    }
    return HV_OK;
}

/* Sequential pass for the ambiguous facets: the r-th half-edge of f on {a, b} pointing to g
 * is paired with the r-th such half-edge of g (the reverse rank when g == f, so an edge is
 * never its own twin). Rank pairing is symmetric, so the arcs stay an involution. */
static void resolve_ambiguous(build_ctx *x)
{
    hv_slicer *s = x->s;
    for (size_t f = 0; f < s->nf; ++f) {
        if (!x->ambiguous[f]) continue;
        for (int le = 0; le < 3; ++le) {
            int32_t g = x->nbr[3 * f + (size_t)le];
            if (g < 0) continue;
            uint32_t va = x->tri[3 * f + (size_t)le], vb = x->tri[3 * f + (size_t)(le + 1) % 3];
            int mine[3], theirs[3];
            int km = matching_edges(x->tri, x->nbr, (uint32_t)f, (uint32_t)g, va, vb, mine);
            int kt = matching_edges(x->tri, x->nbr, (uint32_t)g, (uint32_t)f, va, vb, theirs);
            if (km <= 1 && kt <= 1 && (uint32_t)g != f) continue; /* resolved in parallel */
            int r = 0;
            while (r < km && mine[r] != le) ++r;
            if (r == km || km != kt) continue; /* inconsistent pairing: leave open */
            int pick = (uint32_t)g == f ? theirs[kt - 1 - r] : theirs[r];
            if ((uint32_t)g == f && pick == le) continue; /* odd middle one: stays open */
            set_arc(s, (uint32_t)f, k_weight_of_edge[le], g, k_weight_of_edge[pick]);
        }
    }
}

/* ---- z index ------------------------------------------------------------------------------ */

typedef struct zkey {
    double zmin;
    uint32_t f;
} zkey;

static int cmp_zkey(const void *a, const void *b)
{
    const zkey *x = a, *y = b;
    if (x->zmin != y->zmin) return x->zmin < y->zmin ? -1 : 1;
    return x->f < y->f ? -1 : x->f > y->f;
}

static int extent_class(double ext, double base)
{
    if (!(ext > base)) return 0;
    int e;
    frexp(ext / base, &e); /* ext/base in [2^(e-1), 2^e) */
    return HV_MIN(e, HV_SLICE_CLASSES - 1);
}

void hv_slicer_class_range(const hv_slicer *s, int c, double a, double b, size_t *lo,
                           size_t *hi)
{
    size_t l = s->class_start[c], r = s->class_start[c + 1];
    /* first index with zmin >= a */
    size_t x = l, y = r;
    while (x < y) {
        size_t m = x + (y - x) / 2;
        if (s->szmin[m] < a) x = m + 1;
        else y = m;
    }
    *lo = x;
    y = r;
    while (x < y) {
        size_t m = x + (y - x) / 2;
        if (s->szmin[m] < b) x = m + 1;
        else y = m;
    }
    *hi = x;
}

hv_status hv_slicer_crossing(const hv_slicer *s, double h, uint32_t **buf, size_t *cap,
                             size_t *n)
{
    *n = 0;
    for (int c = 0; c < HV_SLICE_CLASSES; ++c) {
        if (s->class_start[c] == s->class_start[c + 1]) continue;
        double ext = s->class_ext[c];
        /* a facet with zmin < h - ext has zmax < h; the margin absorbs the rounding of the
         * subtraction (extra candidates are filtered exactly below) */
        double a = h - ext - (ext + fabs(h)) * 1e-12 - DBL_MIN;
        size_t lo, hi;
        hv_slicer_class_range(s, c, a, h, &lo, &hi);
        if (hi > lo && hv_grow((void **)buf, cap, *n + (hi - lo), sizeof **buf) != HV_OK)
            return HV_ERR_NOMEM;
        uint32_t *out = *buf;
        size_t k = *n;
        for (size_t i = lo; i < hi; ++i)
            if (s->szmax[i] >= h) out[k++] = s->order[i];
        *n = k;
    }
    return HV_OK;
}

/* ---- create / destroy ---------------------------------------------------------------------- */

void hv_slicer_destroy(hv_slicer *s)
{
    if (!s) return;
    free(s->xyz);
    free(s->tri);
    free(s->arc);
    free(s->back);
    free(s->nxy);
    free(s->order);
    free(s->szmin);
    free(s->szmax);
    free(s->body_first);
    free(s->body_inverted);
    free(s);
}

/* The facets of a multi-body mesh with each body welded alone (hv_mesh_body_extract): vertices
 * (as doubles) and facets concatenated body by body, the neighbours and edge flags of each body's
 * own adjacency, so no arc joins two bodies even where they share vertices or edges. Facet f is
 * the mesh's facet f. The arrays are malloc'd (*nv vertices). */
static hv_status split_bodies(const hv_mesh *mesh, hv_slicer *s, size_t *nv_out, uint32_t **tri_out, int32_t **nbr_out,
                              uint8_t **ef_out)
{
    size_t nb = hv_mesh_body_count(mesh), nf = hv_mesh_facet_count(mesh), nv = 0;
    uint32_t *tri = hv_malloc_array(3 * nf, sizeof *tri);
    int32_t *nbr = hv_malloc_array(3 * nf, sizeof *nbr);
    uint8_t *ef = hv_malloc(nf);
    double *xyz = NULL;
    size_t cap = 0;
    hv_status st = tri && nbr && ef ? HV_OK : HV_ERR_NOMEM;
    for (size_t b = 0; b < nb && st == HV_OK; ++b) {
        hv_mesh *bm = NULL;
        if ((st = hv_mesh_body_extract(mesh, b, &bm)) != HV_OK) break;
        size_t bv = hv_mesh_vertex_count(bm), bf = hv_mesh_facet_count(bm), f0 = s->body_first[b];
        if ((st = hv_grow((void **)&xyz, &cap, 3 * (nv + bv), sizeof *xyz)) == HV_OK) {
            const float *v = hv_mesh_vertices(bm);
            for (size_t i = 0; i < 3 * bv; ++i) xyz[3 * nv + i] = (double)v[i];
            const uint32_t *t = hv_mesh_facets(bm);
            const int32_t *n = hv_mesh_neighbors(bm);
            const uint8_t *e = hv_mesh_edge_flags(bm);
            for (size_t i = 0; i < 3 * bf; ++i) {
                tri[3 * f0 + i] = t[i] + (uint32_t)nv;
                nbr[3 * f0 + i] = n[i] < 0 ? n[i] : n[i] + (int32_t)f0;
            }
            for (size_t i = 0; i < bf; ++i) ef[f0 + i] = e ? e[i] : 0;
            nv += bv;
        }
        hv_mesh_destroy(bm);
    }
    if (st == HV_OK && nv > (size_t)UINT32_MAX) st = hv_error_set(HV_ERR_LIMIT, "slicer: %zu vertices", nv);
    if (st != HV_OK) {
        free(tri);
        free(nbr);
        free(ef);
        free(xyz);
        return st;
    }
    free(s->xyz);
    s->xyz = xyz;
    *nv_out = nv;
    *tri_out = tri;
    *nbr_out = nbr;
    *ef_out = ef;
    return HV_OK;
}

typedef struct z_ctx {
    hv_slicer *s;
    zkey *keys;
    double *zmax;
    uint8_t *cls;
    double base;
} z_ctx;

static hv_status zrange_range(void *c, size_t b, size_t e, int t)
{
    (void)t;
    z_ctx *x = c;
    const hv_slicer *s = x->s;
    for (size_t f = b; f < e; ++f) {
        const uint32_t *v = s->tri + 3 * f;
        double z0 = s->xyz[3 * (size_t)v[0] + 2], z1 = s->xyz[3 * (size_t)v[1] + 2],
               z2 = s->xyz[3 * (size_t)v[2] + 2];
        double lo = HV_MIN(z0, HV_MIN(z1, z2)), hi = HV_MAX(z0, HV_MAX(z1, z2));
        x->keys[f].zmin = lo;
        x->keys[f].f = (uint32_t)f;
        x->zmax[f] = hi;
        x->cls[f] = (uint8_t)extent_class(hi - lo, x->base);
    }
    return HV_OK;
}

static hv_status build_index(hv_slicer *s, const hv_progress *progress)
{
    size_t nf = s->nf;
    zkey *keys = hv_malloc_array(nf, sizeof *keys);
    zkey *sorted = hv_malloc_array(nf, sizeof *sorted);
    double *zmax = hv_malloc_array(nf, sizeof *zmax);
    uint8_t *cls = hv_malloc(nf);
    s->order = hv_malloc_array(nf, sizeof *s->order);
    s->szmin = hv_malloc_array(nf, sizeof *s->szmin);
    s->szmax = hv_malloc_array(nf, sizeof *s->szmax);
    hv_status st = HV_ERR_NOMEM;
    if (!keys || !sorted || !zmax || !cls || !s->order || !s->szmin || !s->szmax) goto done;

    double zr = s->info.bbox_max[2] - s->info.bbox_min[2];
    z_ctx x = {s, keys, zmax, cls, zr > 0 ? ldexp(zr, -30) : 1.0};
    st = hv_parallel_for(nf, GRAIN, zrange_range, &x, NULL, "slicer");
    if (st != HV_OK) goto done;

    /* counting sort by class, then each class by (zmin, facet) */
    size_t count[HV_SLICE_CLASSES] = {0};
    for (size_t f = 0; f < nf; ++f) ++count[cls[f]];
    s->class_start[0] = 0;
    for (int c = 0; c < HV_SLICE_CLASSES; ++c) s->class_start[c + 1] = s->class_start[c] + count[c];
    size_t pos[HV_SLICE_CLASSES];
    memcpy(pos, s->class_start, sizeof pos);
    for (size_t f = 0; f < nf; ++f) sorted[pos[cls[f]]++] = keys[f];
    for (int c = 0; c < HV_SLICE_CLASSES; ++c) {
        size_t b = s->class_start[c], n = count[c];
        if (n > 1) qsort(sorted + b, n, sizeof *sorted, cmp_zkey);
        double ext = 0;
        for (size_t i = b; i < b + n; ++i) {
            uint32_t f = sorted[i].f;
            s->order[i] = f;
            s->szmin[i] = sorted[i].zmin;
            s->szmax[i] = zmax[f];
            ext = HV_MAX(ext, zmax[f] - sorted[i].zmin);
        }
        s->class_ext[c] = ext;
        st = hv_progress_report(progress, "slicer", 0.5 + 0.5 * (double)(c + 1) / HV_SLICE_CLASSES);
        if (st != HV_OK) goto done;
    }
    st = HV_OK;
done:
    free(keys);
    free(sorted);
    free(zmax);
    free(cls);
    return st;
}

/* The box of the slicer's vertices (nv of them). */
static void bounding_box(hv_slicer *s, size_t nv)
{
    hv_slicer_info *in = &s->info;
    for (int a = 0; a < 3; ++a) {
        in->bbox_min[a] = nv ? s->xyz[a] : 0;
        in->bbox_max[a] = in->bbox_min[a];
    }
    for (size_t v = 0; v < nv; ++v)
        for (int a = 0; a < 3; ++a) {
            double q = s->xyz[3 * v + (size_t)a];
            if (q < in->bbox_min[a]) in->bbox_min[a] = q;
            if (q > in->bbox_max[a]) in->bbox_max[a] = q;
        }
}

/* Per facet the unit horizontal normal (the orientation vote), and the signed volume of each
 * body about the box centre (divergence theorem): an inside-out body has every loop's vote
 * reversed. */
static hv_status orientation(hv_slicer *s, const uint32_t *tri)
{
    const size_t nf = s->nf;
    const hv_slicer_info *in = &s->info;
    s->nxy = hv_malloc_array(2 * nf, sizeof *s->nxy);
    if (!s->nxy) return HV_ERR_NOMEM;
    double c[3], vol6 = 0;
    size_t body = 0;
    for (int a = 0; a < 3; ++a) c[a] = 0.5 * (in->bbox_min[a] + in->bbox_max[a]);
    for (size_t f = 0; f < nf; ++f) {
        if (f == s->body_first[body + 1]) {
            s->body_inverted[body++] = vol6 < 0;
            vol6 = 0;
        }
        const double *p = s->xyz + 3 * (size_t)tri[3 * f], *q = s->xyz + 3 * (size_t)tri[3 * f + 1],
                     *r = s->xyz + 3 * (size_t)tri[3 * f + 2];
        double ax = p[0] - c[0], ay = p[1] - c[1], az = p[2] - c[2];
        double bx = q[0] - c[0], by = q[1] - c[1], bz = q[2] - c[2];
        double cx = r[0] - c[0], cy = r[1] - c[1], cz = r[2] - c[2];
        vol6 += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
        double ux = bx - ax, uy = by - ay, uz = bz - az, vx = cx - ax, vy = cy - ay, vz = cz - az;
        double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, len = sqrt(nx * nx + ny * ny);
        s->nxy[2 * f] = len > 0 ? (float)(nx / len) : 0.0f;
        s->nxy[2 * f + 1] = len > 0 ? (float)(ny / len) : 0.0f;
    }
    s->body_inverted[body] = vol6 < 0;
    s->inverted = s->body_inverted[0];
    return HV_OK;
}

/* The traversal relies on arcs being an involution: any arc whose twin disagrees is dropped;
 * then the open edges, arcs and non-manifold arcs are counted. */
static void check_arcs(hv_slicer *s, const uint8_t *eflags)
{
    const size_t nf = s->nf;
    hv_slicer_info *in = &s->info;
    for (size_t f = 0; f < nf; ++f)
        for (int w = 1; w <= 3; ++w) {
            int32_t g = s->arc[3 * f + (size_t)(w - 1)];
            if (g < 0) continue;
            int wg = hv_wdg_back(s, f, w);
            if (wg < 1 || s->arc[3 * (size_t)g + (size_t)(wg - 1)] != (int32_t)f ||
                hv_wdg_back(s, (size_t)g, wg) != w)
                set_arc(s, (uint32_t)f, w, -1, 0);
        }
    for (size_t f = 0; f < nf; ++f)
        for (int le = 0; le < 3; ++le) {
            int w = k_weight_of_edge[le];
            if (s->arc[3 * f + (size_t)(w - 1)] < 0) {
                ++in->open_edges;
            } else {
                ++in->arcs;
                if (eflags && (eflags[f] >> le) & 1) ++in->nonmanifold_arcs;
            }
        }
}

hv_status hv_slicer_create(const hv_mesh *mesh, const hv_progress *progress, hv_slicer **out)
{
    if (!out) return hv_error_set(HV_ERR_INVALID, "hv_slicer_create: out is NULL");
    *out = NULL;
    if (!mesh || hv_mesh_facet_count(mesh) == 0)
        return hv_error_set(HV_ERR_INVALID, "hv_slicer_create: mesh has no facets");
    size_t nf = hv_mesh_facet_count(mesh), nv = hv_mesh_vertex_count(mesh);
    if (nf > (size_t)INT32_MAX)
        return hv_error_set(HV_ERR_LIMIT, "slicer: %zu facets (at most %d)", nf, INT32_MAX);
    hv_slicer *s = hv_calloc(1, sizeof *s);
    if (!s) return HV_ERR_NOMEM;
    s->nf = nf;
    s->nv = nv;
    s->nbodies = hv_mesh_body_count(mesh);
    s->xyz = hv_malloc_array(3 * nv, sizeof *s->xyz);
    s->tri = hv_malloc_array(3 * nf, sizeof *s->tri);
    s->arc = hv_malloc_array(3 * nf, sizeof *s->arc);
    s->back = hv_malloc(nf);
    s->body_first = hv_malloc_array(s->nbodies + 1, sizeof *s->body_first);
    s->body_inverted = hv_calloc(s->nbodies, 1);
    uint8_t *amb = hv_calloc(nf, 1);
    uint32_t *own_tri = NULL;
    int32_t *own_nbr = NULL;
    uint8_t *own_ef = NULL;
    hv_status st = HV_ERR_NOMEM;
    if (!s->xyz || !s->tri || !s->arc || !s->back || !s->body_first || !s->body_inverted || !amb) goto fail;
    for (size_t b = 0; b < s->nbodies; ++b) s->body_first[b] = hv_mesh_body_at(mesh, b)->first_facet;
    s->body_first[s->nbodies] = nf;

    const uint32_t *tri = hv_mesh_facets(mesh);
    const int32_t *nbr = hv_mesh_neighbors(mesh);
    const uint8_t *eflags = hv_mesh_edge_flags(mesh);
    if (s->nbodies > 1) {
        /* each body sliced from its own facets: welded alone, its own arcs */
        if ((st = split_bodies(mesh, s, &nv, &own_tri, &own_nbr, &own_ef)) != HV_OK) goto fail;
        s->nv = nv;
        tri = own_tri;
        nbr = own_nbr;
        eflags = own_ef;
    } else {
        const float *xyz = hv_mesh_vertices(mesh);
        for (size_t i = 0; i < 3 * nv; ++i) s->xyz[i] = (double)xyz[i];
    }
    memcpy(s->tri, tri, 3 * nf * sizeof *tri);
    hv_slicer_info *in = &s->info;
    in->facets = nf;
    bounding_box(s, nv);
    if ((st = orientation(s, tri)) != HV_OK) goto fail;

    st = hv_progress_report(progress, "slicer", 0.0);
    if (st != HV_OK) goto fail;
    build_ctx bx = {s, tri, nbr, amb};
    st = hv_parallel_for(nf, GRAIN, arcs_range, &bx, NULL, "slicer");
    if (st != HV_OK) goto fail;
    resolve_ambiguous(&bx);

    check_arcs(s, eflags);
    st = hv_progress_report(progress, "slicer", 0.5);
    if (st != HV_OK) goto fail;
    st = build_index(s, progress);
    if (st != HV_OK) goto fail;
    free(amb);
    free(own_tri);
    free(own_nbr);
    free(own_ef);
    *out = s;
    return HV_OK;
fail:
    free(amb);
    free(own_tri);
    free(own_nbr);
    free(own_ef);
    hv_slicer_destroy(s);
    return st;
}

void hv_slicer_get_info(const hv_slicer *s, hv_slicer_info *info)
{
    if (s && info) *info = s->info;
}

hv_status hv_slicer_arc(const hv_slicer *s, size_t facet, int weight, int32_t *neighbor,
                        int *neighbor_weight)
{
    if (!s || facet >= s->nf || weight < 1 || weight > 3)
        return hv_error_set(HV_ERR_INVALID, "hv_slicer_arc: facet %zu weight %d out of range",
                            facet, weight);
    int32_t g = s->arc[3 * facet + (size_t)(weight - 1)];
    if (neighbor) *neighbor = g < 0 ? HV_MESH_OPEN : g;
    if (neighbor_weight) *neighbor_weight = g < 0 ? 0 : hv_wdg_back(s, facet, weight);
    return HV_OK;
}
