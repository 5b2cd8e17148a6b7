/* src/geometry/leaf.c - the leaf interface (hovox/solid.h): a leaf of a geometry record opened
 * through its kind's table entry, and the MESH kind: the placed mesh cut by the WDG slicer
 * (Wu 2.4.1). Layer 3 of README's Layout, above the WDG slicer it cuts meshes with. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "geometry_internal.h"

struct hv_leaf {
    const hv_leaf_ops *ops;
    void *state;
};

/* ---- MESH ------------------------------------------------------------------------------------- */

typedef struct mesh_leaf {
    const hv_mesh *mesh;
    int owned; /* 0: the caller's mesh (hv_leaf_wrap_mesh) */
    hv_slicer *slicer;
} mesh_leaf;

static void mesh_close(void *state)
{
    mesh_leaf *m = state;
    if (!m) return;
    hv_slicer_destroy(m->slicer);
    if (m->owned) hv_mesh_destroy((hv_mesh *)m->mesh);
    free(m);
}

static hv_status mesh_open(const hv_geometry *g, size_t i, const hv_progress *progress, void **state)
{
    *state = NULL;
    mesh_leaf *m = hv_calloc(1, sizeof *m);
    if (!m) return HV_ERR_NOMEM;
    hv_mesh *mesh = NULL;
    hv_status s = hv_geometry_leaf_mesh(g, i, &mesh);
    m->mesh = mesh;
    m->owned = 1;
    if (s == HV_OK) s = hv_slicer_create(m->mesh, progress, &m->slicer);
    if (s != HV_OK) {
        mesh_close(m);
        return s;
    }
    *state = m;
    return HV_OK;
}

static void mesh_bbox(const void *state, double min[3], double max[3])
{
    hv_slicer_info info;
    hv_slicer_get_info(((const mesh_leaf *)state)->slicer, &info);
    memcpy(min, info.bbox_min, sizeof info.bbox_min);
    memcpy(max, info.bbox_max, sizeof info.bbox_max);
}

static hv_status mesh_slice(const void *state, double z, const hv_slice_options *o, hv_slice **out)
{
    return hv_slicer_slice(((const mesh_leaf *)state)->slicer, z, o, out);
}

const hv_leaf_ops hv_leaf_mesh_ops = {HV_LEAF_MESH, mesh_open, mesh_close, mesh_bbox, mesh_slice, NULL};

/* ---- the table of kinds --------------------------------------------------------------------------- */

static const hv_leaf_ops *const k_kinds[] = {
    [HV_LEAF_MESH] = &hv_leaf_mesh_ops,
    [HV_LEAF_FIELD_ISO] = &hv_leaf_field_ops, /* the scanned-volume module's (field_leaf.c) */
};

int hv_slice_point_inside(const hv_slice *slice, double x, double y)
{
    const hv_slice_loop *L = hv_slice_loops(slice);
    size_t n = hv_slice_loop_count(slice);
    int winding = 0;
    for (size_t l = 0; l < n; ++l) {
        if (!L[l].closed) continue;
        const double *p = L[l].xy;
        for (size_t i = 0, j = L[l].count - 1; i < L[l].count; j = i++) {
            double yi = p[2 * i + 1], yj = p[2 * j + 1];
            if ((yi > y) == (yj > y)) continue;
            double xc = p[2 * i] + (y - yi) / (yj - yi) * (p[2 * j] - p[2 * i]);
            if (x < xc) winding += yi > yj ? 1 : -1; /* edge j -> i going up: +1 */
        }
    }
    return winding != 0;
}

hv_status hv_leaf_open(const hv_geometry *g, size_t i, const hv_progress *progress, hv_leaf **out)
{
    *out = NULL;
    const hv_geometry_leaf *info = hv_geometry_leaf_at(g, i);
    if (!info) return hv_error_set(HV_ERR_INVALID, "geometry: no leaf %zu (the record has %zu)", i, hv_geometry_leaf_count(g));
    const hv_leaf_ops *ops = (unsigned)info->kind < sizeof k_kinds / sizeof *k_kinds ? k_kinds[info->kind] : NULL;
    if (!ops)
        return hv_error_set(HV_ERR_UNSUPPORTED, "geometry: leaf '%s' is a %s, which this build cannot cut", info->name,
                            info->kind == HV_LEAF_FIELD_ISO ? "field iso-surface" : "leaf of an unknown kind");
    hv_leaf *l = hv_calloc(1, sizeof *l);
    if (!l) return HV_ERR_NOMEM;
    l->ops = ops;
    hv_status s = ops->open(g, i, progress, &l->state);
    if (s != HV_OK) {
        free(l);
        return s;
    }
    *out = l;
    return HV_OK;
}

hv_status hv_leaf_wrap_mesh(const hv_mesh *mesh, const hv_progress *progress, hv_leaf **out)
{
    *out = NULL;
    hv_leaf *l = hv_calloc(1, sizeof *l);
    mesh_leaf *m = hv_calloc(1, sizeof *m);
    hv_status s = l && m ? hv_slicer_create(mesh, progress, &m->slicer) : HV_ERR_NOMEM;
    if (s != HV_OK) {
        free(l);
        free(m);
        return s;
    }
    m->mesh = mesh;
    l->ops = &hv_leaf_mesh_ops;
    l->state = m;
    *out = l;
    return HV_OK;
}

void hv_leaf_close(hv_leaf *l)
{
    if (!l) return;
    l->ops->close(l->state);
    free(l);
}

hv_leaf_kind hv_leaf_get_kind(const hv_leaf *l) { return l->ops->kind; }

void hv_leaf_bbox(const hv_leaf *l, double min[3], double max[3]) { l->ops->bbox(l->state, min, max); }

hv_status hv_leaf_slice(const hv_leaf *l, double z, const hv_slice_options *o, hv_slice **out)
{
    *out = NULL;
    if (!isfinite(z)) return hv_error_set(HV_ERR_INVALID, "geometry: height z = %g is not finite", z);
    return l->ops->slice(l->state, z, o, out);
}

int hv_leaf_inside(const hv_leaf *l, const double p[3])
{
    if (l->ops->inside) return l->ops->inside(l->state, p);
    double lo[3], hi[3];
    l->ops->bbox(l->state, lo, hi);
    for (int a = 0; a < 3; ++a)
        if (!(p[a] >= lo[a] && p[a] <= hi[a])) return 0;
    hv_slice *sl;
    if (l->ops->slice(l->state, p[2], NULL, &sl) != HV_OK) return 0;
    int in = hv_slice_point_inside(sl, p[0], p[1]);
    hv_slice_destroy(sl);
    return in;
}

const hv_mesh *hv_leaf_mesh(const hv_leaf *l) { return l->ops->kind == HV_LEAF_MESH ? ((const mesh_leaf *)l->state)->mesh : NULL; }

const hv_slicer *hv_leaf_slicer(const hv_leaf *l)
{
    return l->ops->kind == HV_LEAF_MESH ? ((const mesh_leaf *)l->state)->slicer : NULL;
}
