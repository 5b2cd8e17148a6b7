/* src/geometry/solid.c - the solid of a geometry record (hovox/solid.h), its exact shape: its
 * leaves opened and its Boolean tree (Wu eq. 27-30, CSG subtract; the shape each op leaves is in
 * hovox/geometry.h) evaluated over their answers. Layer 9 of README's Layout. */
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
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
