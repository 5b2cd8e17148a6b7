/* src/colour/mesh_colour.c - a coloured mesh printed in its colours in one step (issue 29: `layers
 * MESH` and a tray's mesh part): the rule that says which bodies print in their colours (after the
 * 3MF Materials extension), and the model voxelized and painted (hv_colour_paint), an assembly's
 * bodies made of a resin or a composite kept in it. */
#include <math.h>
#include <stdlib.h>

#include <stdio.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/colour.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"

/* Is the material named `name` (the file's text) a resin: of the printer's table, or one the caller
 * prints in a resin (its mapping, by the name the material takes in a model)? */
static int is_resin(const char *name, const hv_colour_body_rule *rule)
{
    if (hv_resin_find(name)) return 1;
    if (!rule || !rule->is_resin) return 0;
    char model_name[65];
    hv_material_name_from(name, model_name);
    return rule->is_resin(rule->user, model_name) != 0;
}

/* Does body i print in its colours? The 3MF Materials extension's colour groups (entries
 * "#rrggbb") are colour and nothing else; an OBJ's materials are its MTL's appearances; a 3MF
 * base material is what the body is made of (the core specification keeps its displaycolor for
 * rendering: "a producer MUST NOT assume that displaycolor has any effect on the printed part"),
 * so it prints in it unless the user asks for colour and it is no resin (the printer's table or
 * the caller's mapping); a composite prints in its mixture; a resin stays in the resin; a body
 * the user gave a colour takes it. */
static int body_paints(const hv_mesh *mesh, size_t i, const hv_colour_body_rule *rule, int obj)
{
    const hv_mesh_body *b = hv_mesh_body_at(mesh, i);
    if (b->coloured || b->material == HV_MESH_NO_MATERIAL) return 1;
    const hv_mesh_material *mm = hv_mesh_material_at(mesh, (size_t)b->material);
    if (mm->nparts) return 0;
    if (mm->name[0] == '#') return 1;
    if (is_resin(mm->name, rule)) return 0;
    return obj || (rule && rule->asked);
}

size_t hv_colour_mesh_bodies(const hv_mesh *mesh, const hv_colour_body_rule *rule, uint8_t *paint)
{
    int obj = hv_mesh_get_report(mesh)->format == HV_MESH_OBJ;
    size_t n = 0;
    for (size_t i = 0; i < hv_mesh_body_count(mesh); ++i) {
        int p = body_paints(mesh, i, rule, obj);
        if (paint) paint[i] = (uint8_t)p;
        n += (size_t)p;
    }
    return n;
}

int hv_colour_mesh_paints(const hv_mesh *mesh, const hv_colour_body_rule *rule)
{
    hv_colour_body_rule unasked = {0, rule ? rule->is_resin : NULL, rule ? rule->user : NULL};
    return hv_mesh_has_colour(mesh) && hv_colour_mesh_bodies(mesh, &unasked, NULL) > 0;
}

/* A copy of the mesh whose facets of bodies that keep their materials have no colour, so
 * painting carries colour from the painted bodies' surfaces alone. */
static hv_status colour_bodies_only(const hv_mesh *mesh, const uint8_t *paint, hv_mesh **out)
{
    static const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    size_t nf = hv_mesh_facet_count(mesh);
    hv_status s = hv_mesh_transform(mesh, id, out);
    float *uv = s == HV_OK ? hv_calloc(nf ? nf : 1, 6 * sizeof *uv) : NULL;
    int32_t *ft = s == HV_OK ? hv_malloc_array(nf ? nf : 1, sizeof *ft) : NULL;
    if (s == HV_OK && (!uv || !ft)) s = HV_ERR_NOMEM;
    if (s == HV_OK) {
        const float *u0 = hv_mesh_corner_uvs(*out);
        const int32_t *t0 = hv_mesh_facet_textures(*out);
        if (u0) memcpy(uv, u0, nf * 6 * sizeof *uv);
        for (size_t f = 0; f < nf; ++f) ft[f] = t0 ? t0[f] : -1;
        for (size_t i = 0; i < hv_mesh_body_count(*out); ++i) {
            const hv_mesh_body *b = hv_mesh_body_at(*out, i);
            for (size_t f = b->first_facet; !paint[i] && f < b->first_facet + b->facet_count; ++f)
                ft[f] = HV_MESH_NO_COLOUR;
        }
        s = hv_mesh_set_corner_uvs(*out, uv, ft);
    }
    free(uv);
    free(ft);
    if (s != HV_OK) {
        hv_mesh_destroy(*out);
        *out = NULL;
    }
    return s;
}

/* The model's material `name` (hv_material_name_from of it), added with its grid of zeros on
 * the occupancy when the table lacks it. */
static hv_status material_of(hv_volume *vol, hv_material_table *t, const char *text, const float *rgba, size_t n,
                             int *k)
{
    char name[65];
    hv_material_name_from(text, name);
    *k = hv_material_find(t, name);
    if (*k >= 0) return HV_OK;
    hv_status s = hv_material_add(t, name, rgba, k);
    float *zero = s == HV_OK ? hv_calloc(n ? n : 1, sizeof *zero) : NULL;
    if (s == HV_OK && !zero) s = HV_ERR_NOMEM;
    char grid[80];
    snprintf(grid, sizeof grid, "material.%s", name);
    if (s == HV_OK) s = hv_volume_grid_set(vol, grid, "occupancy", zero, n);
    free(zero);
    return s;
}

/* Every voxel of a body that keeps its material (its region) 100 % that material or its
 * composite's mixture, no colour asked for there; then the colour resins no voxel uses leave
 * the table when it holds more than the printer's six (they would take slots for nothing). */
static hv_status keep_materials(hv_volume *vol, const hv_mesh *mesh, const uint8_t *paint)
{
    hv_regions *rg = NULL;
    hv_material_table *t = NULL;
    hv_status s = hv_voxelize_regions_read(vol, &rg);
    if (s == HV_OK) s = hv_material_table_load(vol, &t);
    size_t n = (size_t)hv_volume_mask_count(vol, hv_volume_grid_find(vol, "occupancy"));
    static const char *const k_want[4] = {"colour.r", "colour.g", "colour.b", "colour.mask"};
    for (size_t i = 0; s == HV_OK && i < hv_mesh_body_count(mesh); ++i) {
        int64_t r = paint[i] ? -1 : hv_regions_find(rg, hv_mesh_body_at(mesh, i)->name);
        const hv_region_info *ri = r >= 0 ? hv_regions_at(rg, (size_t)r) : NULL;
        if (!ri || !ri->material) continue;
        int k[HV_MAX_MATERIALS];
        double f[HV_MAX_MATERIALS];
        size_t np = ri->nparts ? ri->nparts : 1;
        for (size_t q = 0; q < np && s == HV_OK; ++q) {
            s = material_of(vol, t, ri->nparts ? ri->parts[q].material : ri->material,
                            ri->has_color && !ri->nparts ? ri->rgba : NULL, n, &k[q]);
            f[q] = ri->nparts ? ri->parts[q].fraction : 1.0;
        }
        int reg = hv_volume_grid_find(vol, ri->grid);
        if (s != HV_OK || reg < 0) break;
        int m = hv_material_count(t), g[HV_MAX_MATERIALS + 4];
        for (int j = 0; j < m; ++j) g[j] = hv_material_grid(vol, t, j);
        for (int j = 0; j < 4; ++j) g[m + j] = hv_volume_grid_find(vol, k_want[j]);
        for (size_t l = 0; l < hv_volume_leaf_count(vol); ++l) {
            const uint64_t *in = hv_volume_leaf_bool_c(vol, reg, l);
            for (unsigned v = 0; v < 512; ++v) {
                if (!((in[v >> 6] >> (v & 63)) & 1u)) continue;
                for (int j = 0; j < m + 4; ++j)
                    if (g[j] >= 0) hv_volume_leaf_float(vol, g[j], l)[v] = 0;
                for (size_t q = 0; q < np; ++q) hv_volume_leaf_float(vol, g[k[q]], l)[v] += (float)f[q];
            }
        }
    }
    /* unused colour resins out, while more than six */
    hv_material_table *kept = NULL;
    if (s == HV_OK && hv_material_count(t) > HV_COLOUR_SLOTS) s = hv_material_table_create(&kept);
    int removed = 0;
    for (int j = 0; kept && s == HV_OK && j < hv_material_count(t); ++j) {
        int g = hv_material_grid(vol, t, j), used = 0;
        for (size_t l = 0; g >= 0 && !used && l < hv_volume_leaf_count(vol); ++l) {
            const float *v = hv_volume_leaf_float_c(vol, g, l);
            for (unsigned x = 0; x < 512 && !used; ++x) used = v[x] != 0;
        }
        if (!used && hv_material_count(t) - removed > HV_COLOUR_SLOTS) {
            ++removed;
            s = hv_volume_grid_remove(vol, g);
            continue;
        }
        float rgba[4];
        hv_material_color(t, j, rgba);
        s = hv_material_add(kept, hv_material_name(t, j), rgba, NULL);
    }
    if (s == HV_OK) s = hv_material_table_store(vol, kept ? kept : t);
    hv_material_table_destroy(kept);
    hv_material_table_destroy(t);
    hv_regions_destroy(rg);
    return s;
}

/* "shell is VeroWhite, core is a mixture" for the message when no body takes colour. */
static void list_bodies(const hv_mesh *mesh, char *buf, size_t size)
{
    size_t at = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < hv_mesh_body_count(mesh) && at + 1 < size; ++i) {
        const hv_mesh_body *b = hv_mesh_body_at(mesh, i);
        const hv_mesh_material *mm = hv_mesh_material_at(mesh, (size_t)b->material);
        int w = snprintf(buf + at, size - at, "%s%s is %s", i ? ", " : "", b->name,
                         mm->nparts ? "a composite" : mm->name);
        at += w > 0 ? (size_t)w : 0;
    }
}

/* The bodies painted (paint[i], one per body; *np of them), or the message when none is and the
 * mesh has colour. */
static hv_status bodies_to_paint(const hv_mesh *mesh, const hv_colour_body_rule *rule, uint8_t **paint, size_t *np)
{
    size_t nb = hv_mesh_body_count(mesh);
    *paint = hv_calloc(nb ? nb : 1, 1);
    if (!*paint) return HV_ERR_NOMEM;
    *np = hv_colour_mesh_bodies(mesh, rule, *paint);
    if (*np || !hv_mesh_has_colour(mesh)) return HV_OK; /* no colour: hv_colour_paint_text says so */
    char bodies[512];
    list_bodies(mesh, bodies, sizeof bodies);
    free(*paint);
    *paint = NULL;
    return hv_error_set(HV_ERR_BAD_INPUT, "%s: no body to paint in its colours: %s (a resin or a composite prints in "
                        "itself)", *hv_mesh_name(mesh) ? hv_mesh_name(mesh) : "the mesh", bodies);
}

hv_status hv_colour_mesh_paint(hv_volume *model, const hv_mesh *mesh, hv_colour_map *map, double depth,
                               const char *core, const hv_colour_body_rule *rule)
{
    uint8_t *paint = NULL;
    size_t np = 0;
    hv_status s = bodies_to_paint(mesh, rule, &paint, &np);
    hv_mesh *own = NULL; /* the painted bodies' colours alone */
    if (s == HV_OK && np && np < hv_mesh_body_count(mesh)) s = colour_bodies_only(mesh, paint, &own);
    if (s == HV_OK) s = hv_colour_paint_text(model, own ? own : mesh, map, depth, core);
    if (s == HV_OK && own) s = keep_materials(model, mesh, paint);
    hv_mesh_destroy(own);
    free(paint);
    return s;
}

hv_status hv_colour_mesh_model(const hv_mesh *mesh, const hv_voxelize_options *vopt, hv_colour_map *map, double depth,
                               const char *core, const hv_colour_body_rule *rule, hv_volume **out)
{
    *out = NULL;
    uint8_t *paint = NULL;
    size_t np = 0;
    hv_status s = bodies_to_paint(mesh, rule, &paint, &np); /* refused before voxelizing */
    free(paint);
    hv_volume *vol = NULL;
    if (s == HV_OK) s = hv_voxelize(mesh, vopt, &vol);
    if (s == HV_OK) s = hv_colour_mesh_paint(vol, mesh, map, depth, core, rule);
    if (s != HV_OK) {
        hv_volume_destroy(vol);
        return s;
    }
    *out = vol;
    return HV_OK;
}

/* Bytes painting takes per occupied voxel: its centre (3 doubles), the six fractions and a core,
 * the requested colour and mask (floats), and the grids they become. */
#define PAINT_BYTES_PER_VOXEL 112.0

hv_status hv_colour_mesh_voxels(const hv_mesh *mesh, double pitch, double depth, uint64_t budget,
                                hv_voxelize_options *opt, hv_voxel_plan *plan)
{
    if (!(pitch > 0) || !(pitch < 1e6) || !(depth > 0) || !(depth < 1e6))
        return hv_error_set(HV_ERR_INVALID, "the voxel pitch and colour depth must be positive, got %g and %g", pitch,
                            depth);
    double v = fmax(pitch, depth / 2), volume = fabs(hv_mesh_get_report(mesh)->volume);
    hv_status s = HV_OK;
    for (int tries = 0; tries <= 60; ++tries, v *= 1.25) {
        opt->voxel_size[0] = opt->voxel_size[1] = opt->voxel_size[2] = v;
        s = hv_voxelize_plan(mesh, opt, plan);
        if (s == HV_OK && (double)plan->memory_bytes + volume / (v * v * v) * PAINT_BYTES_PER_VOXEL <= (double)budget)
            return HV_OK;
        if (s != HV_OK && s != HV_ERR_LIMIT) return s;
    }
    char b[32];
    if (s == HV_OK)
        s = hv_error_set(HV_ERR_LIMIT, "%s: no voxel size from %g mm to %g mm paints it within %s",
                         hv_mesh_name(mesh), fmax(pitch, depth / 2), v / 1.25, hv_size_text(b, sizeof b, (double)budget));
    return s;
}
