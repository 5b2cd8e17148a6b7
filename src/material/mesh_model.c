/* src/material/mesh_model.c - a graded model straight from a mesh in its bodies' materials (issue
 * 27 item 2: one step from an assembly to a stack): the mesh voxelized on one lattice (an assembly
 * into a region per body), each region 100% its body's material or its body's mixture, evaluated. */
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"

/* Every body has a material, checked before any voxel is made. */
static hv_status check_materials(const hv_mesh *mesh)
{
    for (size_t i = 0; i < hv_mesh_body_count(mesh); ++i) {
        const hv_mesh_body *b = hv_mesh_body_at(mesh, i);
        if (b->material == HV_MESH_NO_MATERIAL)
            return hv_error_option(HV_ERR_INVALID, "%s: body '%s' has no material (the mesh names none): give it one "
                                   "with {material} %s=MATERIAL", hv_mesh_name(mesh), b->name, b->name);
    }
    return HV_OK;
}

/* The one body's material (or mixture) as a table and a base composition. */
static hv_status body_table(const hv_mesh *mesh, hv_material_table **table, double base[HV_MAX_MATERIALS])
{
    const hv_mesh_body *b = hv_mesh_body_at(mesh, 0);
    const hv_mesh_material *mm = hv_mesh_material_at(mesh, (size_t)b->material);
    hv_status s = hv_material_table_create(table);
    memset(base, 0, HV_MAX_MATERIALS * sizeof *base);
    for (size_t q = 0; q < HV_MAX(mm->nparts, 1) && s == HV_OK; ++q) {
        char name[65];
        hv_material_name_from(mm->nparts ? mm->parts[q].material : mm->name, name);
        int k = hv_material_find(*table, name);
        if (k < 0) {
            float rgba[4];
            for (int c = 0; c < 4; ++c) rgba[c] = (float)((mm->rgba >> (24 - 8 * c)) & 0xFFu) / 255.0f;
            s = hv_material_add(*table, name, mm->has_color && !mm->nparts ? rgba : NULL, &k);
        }
        if (s == HV_OK) base[k] += mm->nparts ? mm->parts[q].fraction : 1.0;
    }
    if (s != HV_OK) {
        hv_material_table_destroy(*table);
        *table = NULL;
    }
    return s;
}

hv_status hv_mesh_model(const hv_mesh *mesh, const hv_voxelize_options *vopt, const hv_progress *progress,
                        hv_volume **out)
{
    *out = NULL;
    hv_volume *vox = NULL;
    hv_material_table *t = NULL;
    hv_object *obj = NULL;
    double base[HV_MAX_MATERIALS];
    hv_status s = check_materials(mesh);
    if (s == HV_OK && hv_mesh_body_count(mesh) == 1) s = body_table(mesh, &t, base);
    if (s == HV_OK) s = hv_voxelize(mesh, vopt, &vox);
    if (s == HV_OK && t) {
        s = hv_object_create(vox, "occupancy", hv_material_count(t), &obj);
        if (s == HV_OK) s = hv_object_set_base(obj, base);
    } else if (s == HV_OK) {
        s = hv_object_from_regions(vox, NULL, &t, &obj);
        if (s != HV_OK) hv_error_prefix(s, "%s: ", hv_mesh_name(mesh));
    }
    if (s == HV_OK) s = hv_object_evaluate(obj, t, vopt->max_memory, progress, out);
    hv_object_destroy(obj);
    hv_material_table_destroy(t);
    hv_volume_destroy(vox);
    return s;
}

hv_status hv_mesh_model_voxels(const hv_mesh *mesh, double pitch, uint64_t budget, hv_voxelize_options *opt,
                               hv_voxel_plan *plan)
{
    if (!(pitch > 0) || !(pitch < 1e6)) return hv_error_set(HV_ERR_INVALID, "the voxel pitch must be positive, got %g", pitch);
    double v = pitch;
    hv_status s = HV_OK;
    for (int tries = 0; tries <= 60; ++tries, v *= 1.25) {
        opt->voxel_size[0] = opt->voxel_size[1] = opt->voxel_size[2] = v;
        s = hv_voxelize_plan(mesh, opt, plan);
        if (s == HV_OK && plan->memory_bytes <= budget) return HV_OK;
        if (s != HV_OK && s != HV_ERR_LIMIT) return s;
    }
    char b[32];
    if (s == HV_OK)
        s = hv_error_set(HV_ERR_LIMIT, "%s: no voxel size from %g mm to %g mm fits %s", hv_mesh_name(mesh), pitch,
                         v / 1.25, hv_size_text(b, sizeof b, (double)budget));
    return s;
}
