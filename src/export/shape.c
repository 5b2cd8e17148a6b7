/* src/export/shape.c - the model's shape as a surface (issue 28, "Geometry truth"): .stl and .obj
 * exports write the shape the model records, not its voxels. A model whose shape is one recorded
 * mesh (a plain model, or a Boolean of a mesh with itself) is written as that mesh, placed by its
 * transform: exact, watertight when the source was, no stair steps. A Boolean of meshes is a
 * narrow-band level set per mesh, OpenVDB's CSG per node of the tree and volumeToMesh with
 * adaptivity 0 (the OpenVDB bridge, hv_vdb_surface): watertight, 0.05 mm voxels. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "export_internal.h"
#include "hovox/geometry.h"
#include "hovox/material.h"
#include "hovox/mesh.h"
#include "io/vdb/vdb_internal.h"

/* The level-set voxel of a Boolean's surface (mm): finer than a J750's 600 dpi pixels (0.042 mm)
 * is more triangles than any slicer wants; 0.05 mm keeps the holed plate's volume within 0.1% and
 * its flat faces where they are (the level set is exact there). */
#define SHAPE_VOXEL 0.05

/* Bytes the level-set stage needs, as measured (peak RSS, /usr/bin/time -v; the holed plate
 * of tests/cli/cases/holed_plate.py at 10 x 5 x 2.5, 20 x 10 x 5 and 40 x 20 x 10 mm, 88 k to
 * 1.33 M voxels of the leaves' surfaces, on 1 and 2 cores by taskset): 67 / 123 / 376 MiB on one
 * core, 74 / 138 / 408 MiB on two, where the narrow bands alone (6 voxels of 8 bytes, a copy for
 * the CSG, the mesh out: 144 bytes a surface voxel) planned 13 / 48 / 184 MiB. The rest is
 * meshToLevelSet's closest-triangle index grid and its per-thread voxelization grids (OpenVDB's
 * TBB runs on every core of the affinity mask), volumeToMesh's own grids, the allocator's arenas,
 * and the OpenVDB and TBB libraries themselves. Fitted a little over every measurement: per
 * surface voxel (area / v^2) 250 bytes + 20 a thread, plus 40 MiB + 8 MiB a thread (the 8 x 4 x 2 mm
 * plate of the CLI cases, 69 MiB peak, planned 72). */
#define SURFACE_VOXEL_BYTES 250.0
#define SURFACE_VOXEL_BYTES_THREAD 20.0
#define SURFACE_FIXED_BYTES (40.0 * 1048576.0)
#define SURFACE_FIXED_BYTES_THREAD (8.0 * 1048576.0)
static uint64_t surface_bytes(hv_mesh *const *m, size_t n, double v)
{
    double area = 0;
    for (size_t i = 0; i < n; ++i) {
        const float *p = hv_mesh_vertices(m[i]);
        const uint32_t *f = hv_mesh_facets(m[i]);
        for (size_t t = 0; t < hv_mesh_facet_count(m[i]); ++t) {
            const float *a = p + 3 * f[3 * t], *b = p + 3 * f[3 * t + 1], *c = p + 3 * f[3 * t + 2];
            double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            double x = u[1] * w[2] - u[2] * w[1], y = u[2] * w[0] - u[0] * w[2], z = u[0] * w[1] - u[1] * w[0];
            area += 0.5 * sqrt(x * x + y * y + z * z);
        }
    }
    double threads = hv_threads(); /* TBB's workers: --threads (the bridge's limit), at most the processors */
    if (threads > hv_cpus_allowed()) threads = hv_cpus_allowed();
    return (uint64_t)(area / (v * v) * (SURFACE_VOXEL_BYTES + SURFACE_VOXEL_BYTES_THREAD * threads) +
                      SURFACE_FIXED_BYTES + SURFACE_FIXED_BYTES_THREAD * threads);
}

/* The surface of a Boolean tree of meshes: hv_vdb_surface, then outward facets (the signed volume
 * positive) welded into a mesh named after the model. */
static hv_status boolean_surface(const hv_volume *vol, const hv_geometry *g, const hv_export_options *opt,
                                 int plan, hv_export_report *r, hv_mesh **out)
{
    size_t nl = hv_geometry_leaf_count(g), nn = hv_geometry_node_count(g);
    for (size_t i = 0; i < nl; ++i)
        if (hv_geometry_leaf_at(g, i)->kind != HV_LEAF_MESH)
            return hv_error_set(HV_ERR_UNSUPPORTED, "%s: export: the model's shape holds a scanned field's iso-surface; "
                                                    ".stl, .obj and .3mf export Booleans of recorded meshes only",
                                hv_volume_name(vol));
    hv_mesh **m = hv_calloc(nl ? nl : 1, sizeof *m);
    const float **xyz = hv_calloc(nl ? nl : 1, sizeof *xyz);
    const uint32_t **tri = hv_calloc(nl ? nl : 1, sizeof *tri);
    size_t *nv = hv_calloc(nl ? nl : 1, sizeof *nv), *nt = hv_calloc(nl ? nl : 1, sizeof *nt);
    int *ops = hv_calloc(nn ? nn : 1, sizeof *ops);
    uint32_t *leaf = hv_calloc(nn ? nn : 1, sizeof *leaf), *na = hv_calloc(nn ? nn : 1, sizeof *na),
             *nb = hv_calloc(nn ? nn : 1, sizeof *nb);
    float *oxyz = NULL;
    uint32_t *otri = NULL;
    size_t onv = 0, ont = 0;
    hv_status s = m && xyz && tri && nv && nt && ops && leaf && na && nb ? HV_OK : HV_ERR_NOMEM;
    for (size_t i = 0; i < nl && s == HV_OK; ++i) {
        s = hv_geometry_leaf_mesh(g, i, &m[i]);
        if (s != HV_OK) break;
        xyz[i] = hv_mesh_vertices(m[i]);
        tri[i] = hv_mesh_facets(m[i]);
        nv[i] = hv_mesh_vertex_count(m[i]);
        nt[i] = hv_mesh_facet_count(m[i]);
    }
    for (size_t i = 0; i < nn && s == HV_OK; ++i) {
        const hv_geometry_node *nd = hv_geometry_node_at(g, i);
        ops[i] = nd->op;
        leaf[i] = nd->leaf;
        na[i] = nd->a;
        nb[i] = nd->b;
    }
    if (s == HV_OK) {
        r->memory_bytes = surface_bytes(m, nl, SHAPE_VOXEL);
        uint64_t budget = hv_memory_budget(opt->max_memory);
        char need[32], have[32];
        if (budget && r->memory_bytes > budget)
            s = hv_error_option(HV_ERR_LIMIT, "export: the level sets of the shape's %zu meshes at %g mm need %s, "
                                "more than the limit of %s ({max_memory})", nl, SHAPE_VOXEL,
                                hv_size_text(need, sizeof need, (double)r->memory_bytes),
                                hv_size_text(have, sizeof have, (double)budget));
    }
    if (s == HV_OK && !plan)
        s = hv_vdb_surface((int)nl, xyz, nv, tri, nt, (int)nn, ops, leaf, na, nb, SHAPE_VOXEL, &oxyz, &onv, &otri, &ont);
    if (s == HV_OK && !plan) {
        /* outward: OpenVDB's winding is not promised; the signed volume decides */
        double vol6 = 0;
        for (size_t t = 0; t < ont; ++t) {
            const float *a = oxyz + 3 * otri[3 * t], *b = oxyz + 3 * otri[3 * t + 1], *c = oxyz + 3 * otri[3 * t + 2];
            vol6 += (double)a[0] * ((double)b[1] * c[2] - (double)b[2] * c[1]) -
                    (double)a[1] * ((double)b[0] * c[2] - (double)b[2] * c[0]) +
                    (double)a[2] * ((double)b[0] * c[1] - (double)b[1] * c[0]);
        }
        if (vol6 < 0)
            for (size_t t = 0; t < ont; ++t) {
                uint32_t k = otri[3 * t + 1];
                otri[3 * t + 1] = otri[3 * t + 2];
                otri[3 * t + 2] = k;
            }
        s = ont ? hv_mesh_create(oxyz, onv, otri, ont, out)
                : hv_error_set(HV_ERR_INVALID, "%s: export: the model's shape is empty", hv_volume_name(vol));
    }
    free(oxyz);
    free(otri);
    for (size_t i = 0; m && i < nl; ++i) hv_mesh_destroy(m[i]);
    free(m);
    free(xyz);
    free(tri);
    free(nv);
    free(nt);
    free(ops);
    free(leaf);
    free(na);
    free(nb);
    return s;
}

/* The surface of the shape `vol` records; *out owned by the caller. */
static hv_status shape_mesh(const hv_volume *vol, const hv_export_options *opt, int plan, hv_export_report *r,
                            hv_mesh **out)
{
    *out = NULL;
    if (!hv_geometry_present(vol))
        return hv_error_option(HV_ERR_INVALID, "export: the model records no shape (made before hovox recorded the "
                               "meshes a model comes from): export its mesh, or .3mf with {volumetric} for the voxels");
    hv_geometry *g = NULL;
    hv_status s = hv_geometry_read(vol, &g);
    if (s != HV_OK) return hv_error_prefix(s, "export: ");
    if (!hv_geometry_shape_is_leaf(g)) {
        s = boolean_surface(vol, g, opt, plan, r, out);
        hv_buf b = {0};
        for (size_t i = 0; i < hv_geometry_leaf_count(g); ++i)
            hv_buf_printf(&b, "%s%s", i ? ", " : "", hv_geometry_leaf_at(g, i)->name);
        snprintf(r->names, sizeof r->names, "a Boolean of %s, a level set of %g mm voxels", b.data ? b.data : "",
                 SHAPE_VOXEL);
        hv_buf_free(&b);
    } else if (hv_geometry_leaf_at(g, 0)->kind != HV_LEAF_MESH) {
        s = hv_error_set(HV_ERR_UNSUPPORTED, "%s: export: the model's shape is a scanned field's iso-surface; .stl, .obj "
                                             "and .3mf export recorded meshes only", hv_volume_name(vol));
    } else {
        s = hv_geometry_leaf_mesh(g, 0, out);
        snprintf(r->names, sizeof r->names, "%s, the recorded mesh (exact)", hv_geometry_leaf_at(g, 0)->name);
        if (s != HV_OK) s = hv_error_prefix(s, "export: ");
    }
    hv_geometry_destroy(g);
    return s;
}

static void shape_report(const hv_mesh *m, hv_export_report *r)
{
    if (!m) return; /* a Boolean's plan: counted when made */
    r->cells = hv_mesh_facet_count(m);
    r->points = hv_mesh_vertex_count(m);
    /* the mesh as held, about 12 bytes per vertex and 12 per facet, plus the writer's buffer */
    uint64_t held = (uint64_t)(12 * r->points + 12 * r->cells) + (1u << 16);
    /* .3mf: the model part's text, held until it is packed (about 70 bytes a vertex, 48 a triangle) */
    if (r->format == HV_EXPORT_3MF_SHAPE) held += (uint64_t)(72 * r->points + 48 * r->cells);
    if (held > r->memory_bytes) r->memory_bytes = held;
}

hv_status ex_shape_plan(const hv_volume *vol, const hv_export_options *opt, hv_export_report *r)
{
    hv_mesh *m = NULL;
    hv_status s = shape_mesh(vol, opt, 1, r, &m);
    if (s == HV_OK) shape_report(m, r);
    hv_mesh_destroy(m);
    return s;
}

/* Each facet's material: the largest fraction half a voxel inside it (at the centroid where that
 * point is outside the model), HV_MESH_NO_MATERIAL where both are; *def the most frequent. */
static void facet_materials(const hv_volume *vol, const hv_material_table *t, const hv_mesh *m, int32_t *fmat,
                            int32_t *def)
{
    int nm = hv_material_count(t), grids[HV_MAX_MATERIALS];
    for (int k = 0; k < nm; ++k) grids[k] = hv_material_grid(vol, t, k);
    hv_transform xf = hv_volume_get_transform(vol);
    double half = 0.5 * HV_MIN(xf.voxel[0], HV_MIN(xf.voxel[1], xf.voxel[2]));
    const float *p = hv_mesh_vertices(m);
    const uint32_t *f = hv_mesh_facets(m);
    size_t nf = hv_mesh_facet_count(m), count[HV_MAX_MATERIALS] = {0};
    hv_accessor acc;
    hv_accessor_init(&acc, vol);
    for (size_t i = 0; i < nf; ++i) {
        const float *a = p + 3 * f[3 * i], *b = p + 3 * f[3 * i + 1], *c = p + 3 * f[3 * i + 2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), q[3], frac[HV_MAX_MATERIALS];
        int inside = 0;
        fmat[i] = HV_MESH_NO_MATERIAL;
        for (int pass = 0; pass < 2 && !inside; ++pass) {
            double in = pass == 0 && len > 0 ? half / len : 0;
            for (int k = 0; k < 3; ++k) q[k] = ((double)a[k] + b[k] + c[k]) / 3.0 - in * n[k];
            hv_model_probe(&acc, t, grids, q, &inside, frac);
        }
        if (!inside) continue;
        int best = 0;
        for (int k = 1; k < nm; ++k)
            if (frac[k] > frac[best]) best = k;
        fmat[i] = best;
        count[best]++;
    }
    *def = 0;
    for (int k = 1; k < nm; ++k)
        if (count[k] > count[*def]) *def = k;
}

static hv_status write_3mf(const hv_volume *vol, const hv_mesh *m, const char *path, const hv_export_options *opt)
{
    hv_material_table *t = NULL;
    int32_t *fmat = NULL, def = 0;
    hv_status s = hv_material_table_load(vol, &t);
    if (s == HV_ERR_NOT_FOUND) { /* an ungraded model: the shape without materials */
        hv_error_clear();
        s = HV_OK;
        t = NULL;
    }
    if (s == HV_OK && t) {
        fmat = hv_malloc_array(hv_mesh_facet_count(m) ? hv_mesh_facet_count(m) : 1, sizeof *fmat);
        if (!fmat) s = HV_ERR_NOMEM;
        else facet_materials(vol, t, m, fmat, &def);
    }
    int level = opt->zlib_level ? opt->zlib_level : 1; /* as every export: level 6 took 1.35x the CPU for 27% less */
    if (s == HV_OK) s = ex_3mf_shape_write(hv_volume_name(vol), m, t, fmat, def, path, level, opt->progress);
    free(fmat);
    hv_material_table_destroy(t);
    return s;
}

hv_status ex_shape_write(const hv_volume *vol, const char *path, const hv_export_options *opt, hv_export_report *r)
{
    hv_mesh *m = NULL;
    hv_status s = shape_mesh(vol, opt, 0, r, &m);
    if (s == HV_OK) {
        shape_report(m, r);
        s = r->format == HV_EXPORT_OBJ         ? hv_mesh_write_obj(m, path)
            : r->format == HV_EXPORT_3MF_SHAPE ? write_3mf(vol, m, path, opt)
                                               : hv_mesh_write_stl(m, path, 0);
    }
    struct stat st;
    if (s == HV_OK) r->file_bytes = stat(path, &st) == 0 ? (uint64_t)st.st_size : 0;
    hv_mesh_destroy(m);
    return s;
}
