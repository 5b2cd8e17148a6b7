/* src/geometry/solid.c - the solid of a geometry record (hovox/solid.h), its exact shape: its
 * leaves opened and its Boolean tree (Wu eq. 27-30, CSG subtract; the shape each op leaves is in
 * hovox/geometry.h) evaluated over their answers. Layer 3 of README's Layout. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "clipper_bridge.h"
#include "core/internal.h"
#include "core/plugin.h"
#include "geometry_internal.h"

struct hv_solid {
    size_t nleaf, nnode;
    hv_leaf **leaf;
    hv_geometry_node *node;
};

void hv_solid_close(hv_solid *s)
{
    if (!s) return;
    for (size_t i = 0; i < s->nleaf; ++i) hv_leaf_close(s->leaf[i]);
    free(s->leaf);
    free(s->node);
    free(s);
}

hv_status hv_solid_open(const hv_geometry *g, const hv_progress *progress, hv_solid **out)
{
    *out = NULL;
    hv_solid *s = hv_calloc(1, sizeof *s);
    if (!s) return HV_ERR_NOMEM;
    size_t nl = hv_geometry_leaf_count(g), nn = hv_geometry_node_count(g);
    s->leaf = hv_calloc(nl ? nl : 1, sizeof *s->leaf);
    s->node = hv_malloc_array(nn ? nn : 1, sizeof *s->node);
    hv_status st = s->leaf && s->node ? HV_OK : HV_ERR_NOMEM;
    for (size_t i = 0; i < nn && st == HV_OK; ++i) s->node[i] = *hv_geometry_node_at(g, i);
    s->nnode = nn;
    if (hv_geometry_shape_is_leaf(g)) { /* X op X: cut X alone, as a plain record */
        s->node[0] = (hv_geometry_node){-1, 0, 0, 0};
        s->nnode = 1;
    }
    for (size_t i = 0; i < nl && st == HV_OK; ++i, ++s->nleaf) st = hv_leaf_open(g, i, progress, &s->leaf[i]);
    if (st != HV_OK) {
        hv_solid_close(s);
        return st;
    }
    *out = s;
    return HV_OK;
}

size_t hv_solid_leaf_count(const hv_solid *s) { return s->nleaf; }
const hv_leaf *hv_solid_leaf(const hv_solid *s, size_t i) { return i < s->nleaf ? s->leaf[i] : NULL; }
int hv_solid_is_plain(const hv_solid *s) { return s->nleaf == 1 && s->nnode == 1; }

/* The shape an op leaves: 0 a n b, 1 a u b, 2 a, 3 a - b. */
static int op_shape(int op)
{
    switch (op) {
    case HV_GEOMETRY_INTERSECT: return 0;
    case HV_GEOMETRY_UNITE:
    case HV_GEOMETRY_MERGE: return 1;
    case HV_GEOMETRY_DIFFERENCE: return 2;
    default: return 3;
    }
}

void hv_solid_bbox(const hv_solid *s, double min[3], double max[3])
{
    double(*box)[6] = hv_malloc_array(s->nnode, sizeof *box);
    if (!box) { /* no memory: the union of every leaf's box still bounds the shape */
        for (size_t i = 0; i < s->nleaf; ++i) {
            double lo[3], hi[3];
            hv_leaf_bbox(s->leaf[i], lo, hi);
            for (int a = 0; a < 3; ++a) {
                min[a] = i ? HV_MIN(min[a], lo[a]) : lo[a];
                max[a] = i ? HV_MAX(max[a], hi[a]) : hi[a];
            }
        }
        return;
    }
    for (size_t i = 0; i < s->nnode; ++i) {
        const hv_geometry_node *n = &s->node[i];
        double *b = box[i];
        if (n->op < 0) {
            hv_leaf_bbox(s->leaf[n->leaf], b, b + 3);
            continue;
        }
        const double *ba = box[n->a], *bb = box[n->b];
        int k = op_shape(n->op);
        for (int a = 0; a < 3; ++a) {
            b[a] = k == 0 ? HV_MAX(ba[a], bb[a]) : k == 1 ? HV_MIN(ba[a], bb[a]) : ba[a];
            b[a + 3] = k == 0 ? HV_MIN(ba[a + 3], bb[a + 3]) : k == 1 ? HV_MAX(ba[a + 3], bb[a + 3]) : ba[a + 3];
        }
    }
    memcpy(min, box[s->nnode - 1], 3 * sizeof *min);
    memcpy(max, box[s->nnode - 1] + 3, 3 * sizeof *max);
    free(box);
}

/* Inside test of node i, recursively (the tree is at most as deep as the record allows). */
static int node_inside(const hv_solid *s, size_t i, const double p[3])
{
    const hv_geometry_node *n = &s->node[i];
    if (n->op < 0) return hv_leaf_inside(s->leaf[n->leaf], p);
    int a = node_inside(s, n->a, p);
    switch (op_shape(n->op)) {
    case 0: return a && node_inside(s, n->b, p);
    case 1: return a || node_inside(s, n->b, p);
    case 2: return a;
    default: return a && !node_inside(s, n->b, p);
    }
}

int hv_solid_inside(const hv_solid *s, const double p[3]) { return node_inside(s, s->nnode - 1, p); }

/* ---- a solid for a stage ---------------------------------------------------------------------- */

static hv_status solid_of_leaf(hv_leaf *leaf, hv_solid **out)
{
    hv_solid *s = hv_calloc(1, sizeof *s);
    if (s) {
        s->leaf = hv_malloc(sizeof *s->leaf);
        s->node = hv_malloc(sizeof *s->node);
    }
    if (!s || !s->leaf || !s->node) {
        hv_solid_close(s);
        hv_leaf_close(leaf);
        return HV_ERR_NOMEM;
    }
    s->leaf[0] = leaf;
    s->node[0] = (hv_geometry_node){-1, 0, 0, 0};
    s->nleaf = s->nnode = 1;
    *out = s;
    return HV_OK;
}

hv_status hv_solid_from_mesh(const hv_mesh *mesh, const hv_progress *progress, hv_solid **out)
{
    *out = NULL;
    hv_leaf *leaf;
    hv_status s = hv_leaf_wrap_mesh(mesh, progress, &leaf);
    return s == HV_OK ? solid_of_leaf(leaf, out) : s;
}

/* "plate.stl, rod.stl" (the first few leaves' names) into b. */
static void leaf_names(const hv_geometry *g, hv_buf *b)
{
    size_t n = hv_geometry_leaf_count(g);
    for (size_t i = 0; i < n && i < 4; ++i) {
        const char *name = hv_geometry_leaf_at(g, i)->name;
        hv_buf_printf(b, "%s%s", i ? ", " : "", *name ? name : "an unnamed mesh");
    }
    if (n > 4) hv_buf_printf(b, " and %zu more", n - 4);
}

/* 1 when mesh is the placed mesh of g's one leaf, the whole shape (same vertices, facets and
 * bodies). */
static int mesh_matches(const hv_geometry *g, const hv_mesh *mesh, hv_status *st)
{
    *st = HV_OK;
    if (!hv_geometry_shape_is_leaf(g) || hv_geometry_leaf_at(g, 0)->kind != HV_LEAF_MESH) return 0;
    hv_mesh *rec = NULL;
    if ((*st = hv_geometry_leaf_mesh(g, 0, &rec)) != HV_OK) return 0;
    size_t nv = hv_mesh_vertex_count(mesh), nf = hv_mesh_facet_count(mesh);
    int same = nv == hv_mesh_vertex_count(rec) && nf == hv_mesh_facet_count(rec) &&
               hv_mesh_body_count(mesh) == hv_mesh_body_count(rec) &&
               memcmp(hv_mesh_vertices(mesh), hv_mesh_vertices(rec), 12 * nv) == 0 &&
               memcmp(hv_mesh_facets(mesh), hv_mesh_facets(rec), 12 * nf) == 0;
    hv_mesh_destroy(rec);
    return same;
}

hv_status hv_solid_for_model(const hv_volume *model, const hv_mesh *mesh, const char *stage, const char *model_name,
                             const char *mesh_name, const hv_progress *progress, hv_solid **out)
{
    *out = NULL;
    if (!stage) stage = "geometry";
    if (!model_name) model_name = "the model";
    if (!mesh_name) mesh_name = "the mesh";
    int recorded = model && hv_geometry_present(model);
    if (!recorded) {
        if (mesh) return hv_solid_from_mesh(mesh, progress, out);
        if (!model) return hv_error_set(HV_ERR_INVALID, "%s: no model and no mesh", stage);
        return hv_error_set(HV_ERR_INVALID, "%s: %s records no geometry (voxelized by an older hovox, or from no mesh): give its mesh",
                            stage, model_name);
    }
    hv_geometry *g = NULL;
    hv_status s = hv_geometry_read(model, &g);
    if (s != HV_OK) return s == HV_ERR_NOMEM ? s : hv_error_prefix(s, "%s: ", stage);
    if (mesh) {
        int same = mesh_matches(g, mesh, &s);
        if (s == HV_OK && !same) {
            hv_buf b;
            hv_buf_init(&b);
            leaf_names(g, &b);
            if (hv_geometry_shape_is_leaf(g))
                s = hv_error_set(HV_ERR_BAD_INPUT, "%s: %s differs from the mesh the model records (%s): leave the mesh out to cut the recorded one",
                                 stage, mesh_name, b.data ? b.data : "");
            else
                s = hv_error_set(HV_ERR_BAD_INPUT, "%s: %s differs from the shape the model records (a Boolean of %s): leave the mesh out to cut it",
                                 stage, mesh_name, b.data ? b.data : "");
            hv_buf_free(&b);
        } else if (s != HV_OK && s != HV_ERR_NOMEM) {
            s = hv_error_prefix(s, "%s: ", stage);
        }
        hv_geometry_destroy(g);
        return s == HV_OK ? hv_solid_from_mesh(mesh, progress, out) : s;
    }
    s = hv_solid_open(g, progress, out);
    if (s != HV_OK && s != HV_ERR_NOMEM && s != HV_ERR_CANCELLED) s = hv_error_prefix(s, "%s: ", stage);
    hv_geometry_destroy(g);
    return s;
}

/* ---- outlines of the tree: Clipper -------------------------------------------------------------
 * Each leaf's closed loops at z, in integer nanometres, combined node by node with Clipper's
 * Booleans (nonzero fill, as the rasteriser fills a leaf's loops); Wu's difference leaves its
 * first operand's outline as it is. */

static hv_plugin g_clipper = HV_PLUGIN_DEF("hovox-clipper", HV_CLIPPER_ENTRY, HV_CLIPPER_ABI, "Clipper bridge");

#define CLIP_SCALE 1e6 /* mm -> nm */

typedef struct pathset {
    size_t n, cap;
    size_t *count;
    int64_t **xy;
} pathset;

static void pathset_free(pathset *p)
{
    for (size_t i = 0; i < p->n; ++i) free(p->xy[i]);
    free(p->count);
    free(p->xy);
    memset(p, 0, sizeof *p);
}

static int pathset_add(void *user, size_t count, const int64_t *xy)
{
    pathset *p = user;
    if (p->n == p->cap) {
        size_t cap = p->cap ? 2 * p->cap : 16;
        size_t *c = realloc(p->count, cap * sizeof *c);
        if (c) p->count = c;
        int64_t **x = c ? realloc(p->xy, cap * sizeof *x) : NULL;
        if (!x) return HV_ERR_NOMEM;
        p->xy = x;
        p->cap = cap;
    }
    int64_t *copy = hv_malloc_array(count ? 2 * count : 1, sizeof *copy);
    if (!copy) return HV_ERR_NOMEM;
    memcpy(copy, xy, 2 * count * sizeof *copy);
    p->count[p->n] = count;
    p->xy[p->n++] = copy;
    return HV_OK;
}

static hv_status leaf_paths(const hv_leaf *leaf, double z, const hv_slice_options *o, pathset *out)
{
    hv_slice *sl;
    hv_status s = hv_leaf_slice(leaf, z, o, &sl);
    if (s != HV_OK) return s;
    const hv_slice_loop *L = hv_slice_loops(sl);
    int64_t *buf = NULL;
    size_t cap = 0;
    for (size_t l = 0; l < hv_slice_loop_count(sl) && s == HV_OK; ++l) {
        if (!L[l].closed) continue;
        if ((s = hv_grow((void **)&buf, &cap, 2 * L[l].count, sizeof *buf)) != HV_OK) break;
        for (size_t k = 0; k < 2 * L[l].count; ++k) buf[k] = (int64_t)llround(L[l].xy[k] * CLIP_SCALE);
        if (pathset_add(out, L[l].count, buf) != HV_OK) s = HV_ERR_NOMEM;
    }
    free(buf);
    hv_slice_destroy(sl);
    return s;
}

static hv_status clip_status(const hv_clipper_api *api, int r)
{
    if (r == HV_ERR_NOMEM) return hv_error_set(HV_ERR_NOMEM, "out of memory in a Boolean of outlines");
    return hv_error_set((hv_status)r, "%s", api->last_error());
}

static hv_status node_paths(const hv_solid *s, const hv_clipper_api *api, size_t i, double z, const hv_slice_options *o,
                            pathset *out)
{
    const hv_geometry_node *n = &s->node[i];
    if (n->op < 0) return leaf_paths(s->leaf[n->leaf], z, o, out);
    int k = op_shape(n->op);
    if (k == 2) return node_paths(s, api, n->a, z, o, out);
    pathset a = {0}, b = {0};
    hv_status st = node_paths(s, api, n->a, z, o, &a);
    if (st == HV_OK) st = node_paths(s, api, n->b, z, o, &b);
    if (st == HV_OK) {
        int op = k == 0 ? HV_CLIP_INTERSECTION : k == 1 ? HV_CLIP_UNION : HV_CLIP_DIFFERENCE;
        hv_clip_paths pa = {a.n, a.count, (const int64_t *const *)a.xy}, pb = {b.n, b.count, (const int64_t *const *)b.xy};
        int r = api->boolean(op, &pa, &pb, pathset_add, out);
        if (r) st = clip_status(api, r);
    }
    pathset_free(&a);
    pathset_free(&b);
    return st;
}

hv_status hv_solid_slice(const hv_solid *s, double z, const hv_slice_options *o, hv_slice **out)
{
    *out = NULL;
    const hv_geometry_node *root = &s->node[s->nnode - 1];
    if (root->op < 0) return hv_leaf_slice(s->leaf[root->leaf], z, o, out);
    if (!isfinite(z)) return hv_error_set(HV_ERR_INVALID, "geometry: height z = %g is not finite", z);
    const void *t = NULL;
    hv_status st = hv_plugin_api(&g_clipper, &t);
    if (st != HV_OK) return st;
    pathset p = {0};
    st = node_paths(s, t, s->nnode - 1, z, o, &p);
    double **xy = st == HV_OK ? hv_calloc(p.n ? p.n : 1, sizeof *xy) : NULL;
    if (st == HV_OK && !xy) st = HV_ERR_NOMEM;
    for (size_t i = 0; i < p.n && st == HV_OK; ++i) {
        if (!(xy[i] = hv_malloc_array(p.count[i] ? 2 * p.count[i] : 1, sizeof **xy))) st = HV_ERR_NOMEM;
        for (size_t k = 0; st == HV_OK && k < 2 * p.count[i]; ++k) xy[i][k] = (double)p.xy[i][k] / CLIP_SCALE;
    }
    if (st == HV_OK) st = hv_slice_from_loops(z, (const double *const *)xy, p.count, p.n, out);
    for (size_t i = 0; xy && i < p.n; ++i) free(xy[i]);
    free(xy);
    pathset_free(&p);
    return st;
}
