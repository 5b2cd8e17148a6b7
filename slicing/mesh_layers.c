/* slicing/mesh_layers.c - one step from a mesh to a stack (issue 27 item 2, issue 29 item 1): the
 * model a mesh prints with, made in memory on the printer's voxels, in its bodies' materials
 * (hv_mesh_model) or painted in its colours (hv_colour_mesh_model), the colour's manifest hook, and
 * the whole step for the Lua and Python front ends (the CLI's `hovox layers PART.3mf` makes the
 * same model). */
#include <stdio.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/layers.h"
#include "hovox/placement.h"
#include "hovox/voxelize.h"

static int mesh_paints(const hv_mesh *mesh, const hv_layers_mesh_options *mo)
{
    if (mo && mo->materials.n) return 0;
    return (mo && (mo->colour_depth > 0 || mo->core)) || hv_colour_mesh_paints(mesh, NULL);
}

hv_status hv_layers_mesh_model(const hv_mesh *mesh, const hv_layers_options *o, const hv_layers_mesh_options *mo,
                               const hv_progress *progress, hv_volume **model, hv_layers_mesh_voxels *voxels)
{
    *model = NULL;
    if (mo && mo->materials.n && (mo->colour_depth > 0 || mo->core))
        return hv_error_option(HV_ERR_INVALID, "{%s} paints the mesh in its colours; {materials} prints its bodies in "
                               "materials", mo->core ? "core" : "colour_depth");
    double voxel_size = mo ? mo->voxel_size : 0;
    int paint = mesh_paints(mesh, mo);
    double depth = paint && mo && mo->colour_depth > 0 ? mo->colour_depth : HV_COLOUR_DEPTH_DEFAULT;
    hv_voxelize_options vo;
    hv_voxelize_options_init(&vo);
    vo.max_memory = o->max_memory;
    double pitch = HV_MAX(HV_MAX(25.4 / o->dpi[0], 25.4 / o->dpi[1]), o->layer_height);
    uint64_t budget = hv_memory_budget(o->max_memory) / 2;
    hv_voxel_plan plan;
    hv_status s;
    if (voxel_size > 0) {
        vo.voxel_size[0] = vo.voxel_size[1] = vo.voxel_size[2] = voxel_size;
        s = hv_voxelize_plan(mesh, &vo, &plan);
    } else if (paint) { /* the skin two voxels deep: colour is carried from the surface */
        s = hv_colour_mesh_voxels(mesh, pitch, depth, budget, &vo, &plan);
        pitch = HV_MAX(pitch, depth / 2);
    } else {
        s = hv_mesh_model_voxels(mesh, pitch, budget, &vo, &plan);
    }
    if (s != HV_OK) return s;
    if (voxels) {
        voxels->size = vo.voxel_size[0];
        for (int k = 0; k < 3; ++k) voxels->dims[k] = (int64_t)plan.dims[k];
        voxels->coarsened = !(voxel_size > 0) && vo.voxel_size[0] > pitch;
        voxels->painted = paint;
        voxels->depth = paint ? depth : 0;
    }
    if (!paint) return hv_mesh_model(mesh, &vo, progress, model);
    hv_colour_options co;
    hv_colour_options_init(&co);
    hv_colour_map *map = NULL;
    s = hv_colour_map_create(mo ? &mo->colour : &co, &map);
    vo.progress = progress;
    hv_colour_body_rule rule = {mo && (mo->colour_depth > 0 || mo->core), NULL, NULL}; /* layers maps no resins */
    if (s == HV_OK) s = hv_colour_mesh_model(mesh, &vo, map, depth, mo ? mo->core : NULL, &rule, model);
    hv_colour_map_destroy(map);
    return s;
}

hv_status hv_layers_colour_hook(hv_layers_options *o, const hv_volume *model, hv_colour_skin *sk)
{
    memset(sk, 0, sizeof *sk);
    if (!model || o->manifest) return HV_OK;
    hv_status s = hv_colour_map_for_model(model, &sk->map);
    if (s == HV_ERR_NOT_FOUND) {
        hv_error_clear();
        return HV_OK;
    }
    if (s != HV_OK) return s;
    sk->model = model;
    o->manifest = hv_colour_manifest_hook;
    o->manifest_user = sk;
    return HV_OK;
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
    {.key = "colour_depth", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .flags = HV_OPT_LO_OPEN | HV_OPT_UNSET0,
     .offset = OFF(colour_depth), .meta = "MM", .unit = "mm", .section = "Colour (a mesh painted in its colours)",
     .help = "paint the mesh in its colours this deep (default 1 mm; a coloured mesh whose bodies name no 3MF "
             "material is painted without it)"},
    {.key = "core", .kind = HV_OPT_STRING, .offset = OFF(core), .meta = "RESIN|COLOUR",
     .help = "what lies deeper than the colour: a resin or a colour (default the white resin)"},
    HV_COLOUR_OPTIONS(hv_layers_mesh_options, colour, NULL),
};
#undef OFF
static const hv_opt_rule k_mesh_rules[] = {
    {HV_RULE_EXCLUDES, "materials", "colour_depth", NULL, "colour_depth paints the mesh in its colours"},
    {HV_RULE_EXCLUDES, "materials", "core", NULL, "core lies under the mesh's colours"},
};
static void mesh_opts_init(void *p) { memset(p, 0, sizeof(hv_layers_mesh_options)); }
static const hv_option_set k_mesh_set = {"layers mesh", k_mesh_opts, (int)HV_COUNT(k_mesh_opts),
                                         sizeof(hv_layers_mesh_options), mesh_opts_init, k_mesh_rules,
                                         (int)HV_COUNT(k_mesh_rules), NULL, NULL, NULL, 0};
const hv_option_set *hv_layers_mesh_option_set(void) { return &k_mesh_set; }

hv_status hv_layers_write_mesh(const hv_mesh *mesh, const hv_layers_mesh_options *mo, const char *dir,
                               const hv_layers_options *o, const hv_progress *progress, hv_layers_report *report,
                               hv_colour_skin *colour, hv_material_table **table)
{
    hv_layers_report rep;
    memset(&rep, 0, sizeof rep);
    if (colour) memset(colour, 0, sizeof *colour);
    if (table) *table = NULL;
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
    if (s == HV_OK && o->mode != HV_LAYERS_MASK) s = hv_layers_mesh_model(m, o, mo, progress, &model, NULL);
    hv_layers_options lo = *o;
    if (!lo.mesh_name) lo.mesh_name = hv_mesh_name(mesh);
    if (!lo.model_name && model) lo.model_name = lo.mesh_name;
    hv_colour_skin sk; /* a painted model: the skin's dE2000 in the manifest, as the CLI writes it */
    memset(&sk, 0, sizeof sk);
    if (s == HV_OK) s = hv_layers_colour_hook(&lo, model, &sk);
    if (s == HV_OK) s = hv_layers_write(m, model, dir, &lo, progress, &rep);
    if (s == HV_OK && table && rep.materials > 0) s = hv_material_table_load(model, table);
    hv_volume_destroy(model);
    hv_mesh_destroy(m);
    sk.model = NULL;
    if (s == HV_OK && colour) *colour = sk;
    else hv_colour_map_destroy(sk.map);
    if (s != HV_OK) {
        if (table) {
            hv_material_table_destroy(*table);
            *table = NULL;
        }
        return s;
    }
    if (*size_warning) { /* first, as the CLI prints it when it reads the mesh */
        char rest[sizeof rep.warnings];
        snprintf(rest, sizeof rest, "%s", rep.warnings);
        snprintf(rep.warnings, sizeof rep.warnings, "%s%s", size_warning, rest);
    }
    if (report) *report = rep;
    return HV_OK;
}
