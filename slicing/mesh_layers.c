/* slicing/mesh_layers.c - one step from a mesh to a stack (issue 27 item 2): the model a mesh
 * prints with, made in memory on the printer's voxels (hv_mesh_model), and the whole step for the
 * Lua and Python front ends (the CLI's `hovox layers PART.3mf` makes the same model). */
#include <stdio.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/layers.h"
#include "hovox/placement.h"
#include "hovox/voxelize.h"

hv_status hv_layers_mesh_model(const hv_mesh *mesh, const hv_layers_options *o, double voxel_size,
                               const hv_progress *progress, hv_volume **model, hv_layers_mesh_voxels *voxels)
{
    *model = NULL;
    hv_voxelize_options vo;
    hv_voxelize_options_init(&vo);
    vo.max_memory = o->max_memory;
    double pitch = HV_MAX(HV_MAX(25.4 / o->dpi[0], 25.4 / o->dpi[1]), o->layer_height);
    hv_voxel_plan plan;
    hv_status s;
    if (voxel_size > 0) {
        vo.voxel_size[0] = vo.voxel_size[1] = vo.voxel_size[2] = voxel_size;
        s = hv_voxelize_plan(mesh, &vo, &plan);
    } else {
        s = hv_mesh_model_voxels(mesh, pitch, hv_memory_budget(o->max_memory) / 2, &vo, &plan);
    }
    if (s != HV_OK) return s;
    if (voxels) {
        voxels->size = vo.voxel_size[0];
        for (int k = 0; k < 3; ++k) voxels->dims[k] = (int64_t)plan.dims[k];
        voxels->coarsened = !(voxel_size > 0) && vo.voxel_size[0] > pitch;
    }
    return hv_mesh_model(mesh, &vo, progress, model);
}

#define OFF(f) offsetof(hv_layers_mesh_options, f)
static const hv_option k_mesh_opts[] = {
    {.key = "materials", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT | HV_OPT_PAIRS, .offset = OFF(materials),
     .meta = "BODY=MATERIAL", .parse = hv_body_materials_option_parse,
     .help = "the material of a body (an OBJ group, a 3MF item, a file's one body by its name), whatever the file "
             "says"},
    {.key = "voxel_size", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .flags = HV_OPT_LO_OPEN | HV_OPT_UNSET0,
     .offset = OFF(voxel_size), .meta = "MM", .unit = "mm",
     .help = "the voxels the bodies' materials are evaluated on (default: the printer's coarsest pitch, coarsened "
             "to fit half the memory budget)"},
};
#undef OFF
static void mesh_opts_init(void *p) { memset(p, 0, sizeof(hv_layers_mesh_options)); }
static const hv_option_set k_mesh_set = {"layers mesh", k_mesh_opts, (int)HV_COUNT(k_mesh_opts),
                                         sizeof(hv_layers_mesh_options), mesh_opts_init, NULL, 0, NULL, NULL, NULL, 0};
const hv_option_set *hv_layers_mesh_option_set(void) { return &k_mesh_set; }

hv_status hv_layers_write_mesh(const hv_mesh *mesh, const hv_layers_mesh_options *mo, const char *dir,
                               const hv_layers_options *o, const hv_progress *progress, hv_layers_report *report)
{
    hv_layers_report rep;
    memset(&rep, 0, sizeof rep);
    char size_warning[1024] = "";
    const hv_printer_profile *pp = o->profile ? hv_printer_profile_find(o->profile) : NULL;
    if (hv_placement_size_warning(mesh, pp ? pp->build : NULL)) {
        snprintf(size_warning, sizeof size_warning, "%s\n", hv_last_error());
        hv_error_clear();
    }
    hv_mesh *m = NULL;
    hv_volume *model = NULL;
    hv_placement none;
    hv_placement_init(&none);
    hv_status s = hv_placement_transform(&none, mesh, &m); /* a copy: the caller's bodies keep their materials */
    if (s == HV_OK && mo) s = hv_body_materials_apply(&mo->materials, m);
    if (s == HV_OK && o->mode != HV_LAYERS_MASK)
        s = hv_layers_mesh_model(m, o, mo ? mo->voxel_size : 0, progress, &model, NULL);
    hv_layers_options lo = *o;
    if (!lo.mesh_name) lo.mesh_name = hv_mesh_name(mesh);
    if (!lo.model_name && model) lo.model_name = lo.mesh_name;
    if (s == HV_OK) s = hv_layers_write(m, model, dir, &lo, progress, &rep);
    hv_volume_destroy(model);
    hv_mesh_destroy(m);
    if (s != HV_OK) return s;
    if (*size_warning) { /* first, as the CLI prints it when it reads the mesh */
        char rest[sizeof rep.warnings];
        snprintf(rest, sizeof rest, "%s", rep.warnings);
        snprintf(rep.warnings, sizeof rep.warnings, "%s%s", size_warning, rest);
    }
    if (report) *report = rep;
    return HV_OK;
}
