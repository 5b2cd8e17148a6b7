/* src/colour/mesh_colour.c - a coloured mesh printed in its colours in one step (issue 29: `layers
 * MESH` and a tray's mesh part): the rule that says when a mesh's colours are to be printed, and
 * its model voxelized and painted (hv_colour_paint). */
#include <math.h>
#include <stdlib.h>

#include "core/internal.h"
#include "hovox/colour.h"
#include "hovox/voxelize.h"

int hv_colour_mesh_paints(const hv_mesh *mesh)
{
    if (!hv_mesh_has_colour(mesh)) return 0;
    /* an OBJ's materials are its MTL's appearances; a 3MF's named materials (base materials,
     * composites) are what its bodies are made of, and a body made of one prints in it */
    int obj = hv_mesh_get_report(mesh)->format == HV_MESH_OBJ;
    for (size_t i = 0; i < hv_mesh_body_count(mesh); ++i) {
        int32_t k = hv_mesh_body_at(mesh, i)->material;
        if (k == HV_MESH_NO_MATERIAL) continue;
        const hv_mesh_material *mm = hv_mesh_material_at(mesh, (size_t)k);
        if (mm->nparts || (!obj && mm->name[0] != '#')) return 0;
    }
    return 1;
}

hv_status hv_colour_mesh_model(const hv_mesh *mesh, const hv_voxelize_options *vopt, hv_colour_map *map, double depth,
                               const char *core, hv_volume **out)
{
    *out = NULL;
    hv_volume *vol = NULL;
    hv_status s = hv_voxelize(mesh, vopt, &vol);
    if (s == HV_OK) s = hv_colour_paint_text(vol, mesh, map, depth, core);
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
    if (s == HV_OK)
        s = hv_error_set(HV_ERR_LIMIT, "%s: no voxel size from %g mm to %g mm paints it within %.1f MiB",
                         hv_mesh_name(mesh), fmax(pitch, depth / 2), v / 1.25, (double)budget / 1048576.0);
    return s;
}
