/* src/colour/paint.c - colour carried into the part (issue 29, item 1): every occupied voxel within
 * `depth` of the surface takes the colour of its nearest point on the mesh (exact point-triangle
 * distance, Ericson, Real-Time Collision Detection 5.1.5, over a uniform grid of triangle bins of
 * cell size >= depth, so the 27 cells around a voxel hold every triangle within depth), turned into
 * the six resin fractions by the colour map; deeper voxels take the core (a resin, or a colour). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "core/json.h"
#include "hovox/colour.h"
#include "hovox/material.h"
#include "hovox/mesh.h"
#include "hovox/volume.h"

/* Closest point on triangle abc to p; bary receives its weights of a, b, c. */
static void closest_on_triangle(const double p[3], const double a[3], const double b[3], const double c[3],
                                double q[3], double bary[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    for (int k = 0; k < 3; ++k) {
        ab[k] = b[k] - a[k];
        ac[k] = c[k] - a[k];
        ap[k] = p[k] - a[k];
        bp[k] = p[k] - b[k];
        cp[k] = p[k] - c[k];
    }
#define DOT(u, v) ((u)[0] * (v)[0] + (u)[1] * (v)[1] + (u)[2] * (v)[2])
    double d1 = DOT(ab, ap), d2 = DOT(ac, ap), d3 = DOT(ab, bp), d4 = DOT(ac, bp), d5 = DOT(ab, cp),
           d6 = DOT(ac, cp);
#undef DOT
    double u, v, w;
    if (d1 <= 0 && d2 <= 0) { u = 1; v = 0; w = 0; }
    else if (d3 >= 0 && d4 <= d3) { u = 0; v = 1; w = 0; }
    else if (d6 >= 0 && d5 <= d6) { u = 0; v = 0; w = 1; }
    else {
        double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
        if (vc <= 0 && d1 >= 0 && d3 <= 0) {
            double t = d1 / (d1 - d3);
            u = 1 - t; v = t; w = 0;
        } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
            double t = d2 / (d2 - d6);
            u = 1 - t; v = 0; w = t;
        } else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
            double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
            u = 0; v = 1 - t; w = t;
        } else {
            double den = 1 / (va + vb + vc);
            v = vb * den;
            w = vc * den;
            u = 1 - v - w;
        }
    }
    for (int k = 0; k < 3; ++k) q[k] = u * a[k] + v * b[k] + w * c[k];
    bary[0] = u;
    bary[1] = v;
    bary[2] = w;
}

typedef struct bins {
    double lo[3], cell;
    int64_t n[3];
    uint32_t *start; /* n0*n1*n2 + 1 */
    uint32_t *tri;
} bins;

static int64_t cell_of(const bins *g, double x, int a)
{
    int64_t c = (int64_t)floor((x - g->lo[a]) / g->cell);
    return c < 0 ? 0 : c >= g->n[a] ? g->n[a] - 1 : c;
}

/* Every triangle in each cell its bounding box touches (counting sort). */
static hv_status bins_build(bins *g, const hv_mesh *m, double cell)
{
    const hv_mesh_report *r = hv_mesh_get_report(m);
    size_t nf = hv_mesh_facet_count(m);
    const float *v = hv_mesh_vertices(m);
    const uint32_t *t = hv_mesh_facets(m);
    g->cell = cell;
    for (int a = 0; a < 3; ++a) {
        g->lo[a] = r->bbox_min[a];
        g->n[a] = (int64_t)ceil((r->bbox_max[a] - r->bbox_min[a]) / cell) + 1;
        if (g->n[a] > 1024) { /* a coarser grid for large parts: still exact, slower */
            g->cell = (r->bbox_max[a] - r->bbox_min[a]) / 1023;
        }
    }
    for (int a = 0; a < 3; ++a) g->n[a] = (int64_t)ceil((r->bbox_max[a] - r->bbox_min[a]) / g->cell) + 1;
    size_t ncell = (size_t)(g->n[0] * g->n[1] * g->n[2]);
    g->start = hv_calloc(ncell + 1, sizeof *g->start);
    if (!g->start) return HV_ERR_NOMEM;
    for (int pass = 0; pass < 2; ++pass) {
        for (size_t f = 0; f < nf; ++f) {
            int64_t lo[3], hi[3];
            for (int a = 0; a < 3; ++a) {
                double mn = INFINITY, mx = -INFINITY;
                for (int k = 0; k < 3; ++k) {
                    double x = v[3 * (size_t)t[3 * f + (size_t)k] + (size_t)a];
                    mn = x < mn ? x : mn;
                    mx = x > mx ? x : mx;
                }
                lo[a] = cell_of(g, mn, a);
                hi[a] = cell_of(g, mx, a);
            }
            for (int64_t i = lo[0]; i <= hi[0]; ++i)
                for (int64_t j = lo[1]; j <= hi[1]; ++j)
                    for (int64_t k = lo[2]; k <= hi[2]; ++k) {
                        size_t c = (size_t)((i * g->n[1] + j) * g->n[2] + k);
                        if (pass == 0) g->start[c + 1]++;
                        else g->tri[g->start[c]++] = (uint32_t)f;
                    }
        }
        if (pass == 0) {
            for (size_t c = 0; c < ncell; ++c) g->start[c + 1] += g->start[c];
            g->tri = hv_malloc_array(g->start[ncell] ? g->start[ncell] : 1, sizeof *g->tri);
            if (!g->tri) return HV_ERR_NOMEM;
        } else {
            for (size_t c = ncell; c > 0; --c) g->start[c] = g->start[c - 1];
            g->start[0] = 0;
        }
    }
    return HV_OK;
}

/* The nearest point of the mesh to p among the triangles of the 27 cells around p: its facet and
 * weights; returns the distance (INFINITY when no triangle is there). */
static double nearest(const bins *g, const hv_mesh *m, const double p[3], size_t *facet, double bary[3])
{
    const float *v = hv_mesh_vertices(m);
    const uint32_t *t = hv_mesh_facets(m);
    int64_t c[3];
    for (int a = 0; a < 3; ++a) {
        double x = floor((p[a] - g->lo[a]) / g->cell);
        c[a] = (int64_t)x;
    }
    double best = INFINITY;
    for (int64_t i = c[0] - 1; i <= c[0] + 1; ++i)
        for (int64_t j = c[1] - 1; j <= c[1] + 1; ++j)
            for (int64_t k = c[2] - 1; k <= c[2] + 1; ++k) {
                if (i < 0 || j < 0 || k < 0 || i >= g->n[0] || j >= g->n[1] || k >= g->n[2]) continue;
                size_t cell = (size_t)((i * g->n[1] + j) * g->n[2] + k);
                for (uint32_t q = g->start[cell]; q < g->start[cell + 1]; ++q) {
                    size_t f = g->tri[q];
                    double a[3], b[3], cc[3], x[3], w[3];
                    for (int d = 0; d < 3; ++d) {
                        a[d] = v[3 * (size_t)t[3 * f] + (size_t)d];
                        b[d] = v[3 * (size_t)t[3 * f + 1] + (size_t)d];
                        cc[d] = v[3 * (size_t)t[3 * f + 2] + (size_t)d];
                    }
                    closest_on_triangle(p, a, b, cc, x, w);
                    double d2 = (x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1]) + (x[2] - p[2]) * (x[2] - p[2]);
                    if (d2 < best) {
                        best = d2;
                        *facet = f;
                        memcpy(bary, w, sizeof w);
                    }
                }
            }
    return sqrt(best);
}

/* What painting used, for the manifest's dE2000 with the same profile (hv_colour_map_for_model). */
static hv_status record(hv_volume *vol, const hv_colour_map *map, double depth, const char *core, const float *core_rgba)
{
    char hex[10];
    if (!core) {
        unsigned c[3];
        for (int k = 0; k < 3; ++k) c[k] = (unsigned)lrintf(core_rgba[k] * 255.0f);
        snprintf(hex, sizeof hex, "#%02x%02x%02x", c[0] & 255u, c[1] & 255u, c[2] & 255u);
    }
    json_t *doc = json_object(), *resins = json_array();
    int bad = !doc || !resins;
    for (int k = 0; k < HV_COLOUR_SLOTS && !bad; ++k)
        bad |= json_array_append_new(resins, hv_json_text(hv_colour_map_resin(map, k)));
    bad |= hv_json_set(doc, "icc", hv_json_text(hv_colour_map_icc(map)));
    bad |= hv_json_set(doc, "description", hv_json_text(hv_colour_map_description(map)));
    bad |= hv_json_set(doc, "intent", json_string(hv_intent_name(hv_colour_map_intent(map))));
    bad |= hv_json_set(doc, "resins", resins);
    bad |= hv_json_set(doc, "depth_mm", hv_json_number(depth));
    bad |= hv_json_set(doc, "core", hv_json_text(core ? core : hex));
    char *text = bad ? NULL : hv_json_dump(doc);
    json_decref(doc);
    if (!text) return hv_error_set(HV_ERR_NOMEM, "out of memory");
    hv_status s = hv_volume_meta_set_json(vol, "hovox.colour.json", text);
    free(text);
    return s;
}

hv_status hv_colour_paint(hv_volume *vol, const hv_mesh *mesh, hv_colour_map *map, double depth, const char *core,
                          const float *core_rgba)
{
    if (!(depth > 0)) return hv_error_set(HV_ERR_INVALID, "colour depth must be > 0 mm, got %g", depth);
    if (!core && !core_rgba) return hv_error_set(HV_ERR_INVALID, "colour paint: no core resin or colour");
    double *xyz = NULL;
    size_t n = 0;
    hv_status s = hv_volume_centres(vol, "occupancy", &xyz, &n);
    if (s != HV_OK) return s;
    bins g;
    memset(&g, 0, sizeof g);
    if ((s = bins_build(&g, mesh, depth)) != HV_OK) goto done;
    int core_slot = -1; /* core a resin among the six */
    for (int k = 0; core && k < HV_COLOUR_SLOTS; ++k)
        if (strcmp(core, hv_colour_map_resin(map, k)) == 0) core_slot = k;
    int nmat = HV_COLOUR_SLOTS + (core && core_slot < 0 ? 1 : 0);
    /* the fractions, then the requested colour: r, g, b and the mask of voxels that have one */
    float *val = hv_malloc_array(n, (size_t)(nmat + 4) * sizeof *val);
    if (!val) {
        s = HV_ERR_NOMEM;
        goto done;
    }
    float corefr[HV_COLOUR_SLOTS] = {0};
    if (core_rgba) {
        uint8_t c8[4];
        for (int k = 0; k < 4; ++k) c8[k] = (uint8_t)lrintf(core_rgba[k] * 255.0f);
        hv_colour_map_fractions(map, c8, corefr);
    }
    for (size_t i = 0; i < n; ++i) {
        size_t f = 0;
        double bary[3];
        float fr[HV_COLOUR_SLOTS + 1] = {0}, rgba[4], want[4] = {0, 0, 0, 0};
        double d = nearest(&g, mesh, xyz + 3 * i, &f, bary);
        if (d <= depth && hv_mesh_colour_at(mesh, f, bary, rgba)) {
            uint8_t c8[4];
            for (int k = 0; k < 4; ++k) c8[k] = (uint8_t)lrintf(rgba[k] * 255.0f);
            hv_colour_map_fractions(map, c8, fr);
            for (int k = 0; k < 3; ++k) want[k] = c8[k] / 255.0f;
            want[3] = 1;
        } else if (core_rgba) {
            memcpy(fr, corefr, sizeof corefr);
            memcpy(want, core_rgba, 3 * sizeof *want);
            want[3] = 1;
        } else {
            fr[core_slot >= 0 ? core_slot : HV_COLOUR_SLOTS] = 1;
        }
        for (int k = 0; k < nmat; ++k) val[(size_t)k * n + i] = fr[k];
        for (int k = 0; k < 4; ++k) val[(size_t)(nmat + k) * n + i] = want[k];
    }
    /* display colours of slots whose resins the resin table does not know (it colours the J750's) */
    static const float k_show[HV_COLOUR_SLOTS][4] = {{0, 0.6f, 0.9f, 1}, {0.9f, 0, 0.5f, 1}, {1, 0.9f, 0, 1},
                                                      {0.1f, 0.1f, 0.1f, 1}, {1, 1, 1, 1}, {0.8f, 0.9f, 1, 0.3f}};
    hv_material_table *tab = NULL;
    s = hv_material_table_create(&tab);
    for (int k = 0; k < nmat && s == HV_OK; ++k)
        s = hv_material_add(tab, k < HV_COLOUR_SLOTS ? hv_colour_map_resin(map, k) : core,
                            k < HV_COLOUR_SLOTS && !hv_resin_find(hv_colour_map_resin(map, k)) ? k_show[k] : NULL,
                            NULL);
    for (int k = 0; k < nmat && s == HV_OK; ++k) {
        char name[160];
        snprintf(name, sizeof name, "material.%s", k < HV_COLOUR_SLOTS ? hv_colour_map_resin(map, k) : core);
        s = hv_volume_grid_set(vol, name, "occupancy", val + (size_t)k * n, n);
    }
    static const char *const k_want[4] = {"colour.r", "colour.g", "colour.b", "colour.mask"};
    for (int k = 0; k < 4 && s == HV_OK; ++k) s = hv_volume_grid_set(vol, k_want[k], "occupancy", val + (size_t)(nmat + k) * n, n);
    if (s == HV_OK) s = hv_material_table_store(vol, tab);
    if (s == HV_OK) s = record(vol, map, depth, core, core_rgba);
    hv_material_table_destroy(tab);
    free(val);
done:
    free(g.start);
    free(g.tri);
    free(xyz);
    return s;
}

hv_status hv_colour_paint_text(hv_volume *vol, const hv_mesh *mesh, hv_colour_map *map, double depth, const char *core)
{
    if (!hv_mesh_has_colour(mesh))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: no colour to paint (no texture, vertex, face or material colour)",
                            *hv_mesh_name(mesh) ? hv_mesh_name(mesh) : "the mesh");
    float rgba[4];
    if (core && hv_color_parse(core, rgba) == HV_OK) return hv_colour_paint(vol, mesh, map, depth, NULL, rgba);
    hv_error_clear();
    return hv_colour_paint(vol, mesh, map, depth, core ? core : hv_colour_map_resin(map, HV_COLOUR_W), NULL);
}
