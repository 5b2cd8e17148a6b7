/* src/cli/cmd_boolean.c - `hovox boolean A.vdb OP B.vdb -o C.vdb`: Wu's heterogeneous Booleans
 * (eq. 27-30: intersect, union, difference, merge) and CSG subtract of two graded models, the
 * voxels and the recorded shape (issue 28) together; what Lua's obj:intersect(o2) ... do. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "core/internal.h"
#include "hovox/geometry.h"
#include "hovox/material.h"
#include "hovox/model.h"

typedef struct boolean_cli {
    const char *output;
} boolean_cli;

static const hv_option k_local_opts[] = {
    CLI_OUTPUT(boolean_cli, "C.vdb", "the result (written atomically)", 0),
};
static const hv_option_set k_local = CLI_LOCAL_SET("boolean", k_local_opts, boolean_cli);

/* The op names of the command line; "union" is Lua's name of Wu's union (HV_OP_UNITE). */
static const struct {
    const char *name;
    hv_bool_op op;
} k_ops[] = {{"intersect", HV_OP_INTERSECT}, {"union", HV_OP_UNITE},     {"difference", HV_OP_DIFFERENCE},
             {"merge", HV_OP_MERGE},         {"subtract", HV_OP_SUBTRACT}};

/* A graded model's object and materials; errors name the model and the operation. */
static hv_status operand(const char *path, const char *op, hv_volume **vol, hv_object **obj, hv_material_table **t)
{
    hv_status s = hv_model_load(path, vol);
    if (s == HV_OK && (s = hv_material_table_load(*vol, t)) == HV_ERR_NOT_FOUND)
        s = hv_error_set(HV_ERR_BAD_INPUT, "the model has no materials: grade it first ('hovox grade')");
    if (s == HV_OK) s = hv_object_from_model(*vol, obj);
    if (s == HV_OK && hv_geometry_present(*vol)) { /* a damaged shape record is refused here, not later */
        hv_geometry *g = NULL;
        s = hv_geometry_read(*vol, &g);
        hv_geometry_destroy(g);
    }
    if (s != HV_OK && s != HV_ERR_NOMEM && s != HV_ERR_IO) s = hv_error_prefix(HV_ERR_BAD_INPUT, "%s: boolean %s: ", path, op);
    else if (s == HV_ERR_IO) hv_error_prefix(s, "boolean %s: ", op);
    return s;
}

static int run(const cli_args *args, void *lib, void *local)
{
    (void)lib;
    const boolean_cli *c = local;
    if (!c->output) return cli_usage_error("boolean", "missing -o C.vdb");
    const char *opname = args->pos[1];
    int k = -1;
    for (int i = 0; i < (int)HV_COUNT(k_ops); ++i)
        if (strcmp(opname, k_ops[i].name) == 0) k = i;
    if (k < 0)
        return cli_usage_error("boolean", "unknown operation '%s' (intersect, union, difference, merge or subtract)", opname);
    const char *pa = args->pos[0], *pb = args->pos[2];
    hv_volume *va = NULL, *vb = NULL, *out = NULL;
    hv_object *a = NULL, *b = NULL, *h = NULL;
    hv_material_table *ta = NULL, *tb = NULL;
    hv_status s = operand(pa, opname, &va, &a, &ta);
    if (s == HV_OK) s = operand(pb, opname, &vb, &b, &tb);
    for (int j = 0; s == HV_OK && j < hv_material_count(ta); ++j)
        if (j >= hv_material_count(tb) || strcmp(hv_material_name(ta, j), hv_material_name(tb, j)) != 0)
            s = hv_error_set(HV_ERR_BAD_INPUT, "%s: boolean %s: material %d is '%s' here and '%s' in %s: combine models graded with the same materials",
                             pa, opname, j + 1, hv_material_name(ta, j), j < hv_material_count(tb) ? hv_material_name(tb, j) : "none", pb);
    if (s == HV_OK && hv_material_count(ta) != hv_material_count(tb))
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: boolean %s: %d materials against %d in %s", pa, opname, hv_material_count(ta),
                         hv_material_count(tb), pb);
    if (s == HV_OK && (s = hv_object_boolean(a, b, k_ops[k].op, &h)) != HV_OK && s != HV_ERR_NOMEM)
        s = hv_error_prefix(HV_ERR_BAD_INPUT, "%s %s %s: boolean: ", pa, opname, pb);
    if (s == HV_OK) {
        cli_progress bar;
        cli_progress_init(&bar, args->quiet);
        hv_progress prog = {cli_progress_fn, &bar};
        s = hv_object_evaluate(h, ta, 0, &prog, &out);
        cli_progress_done(&bar);
    }
    if (s == HV_OK && (s = hv_volume_save(out, c->output)) != HV_OK) hv_error_prefix(s, "%s: ", c->output);
    if (s == HV_OK && !args->quiet) {
        hv_geometry *g = NULL;
        int leaves = hv_geometry_read(out, &g) == HV_OK ? (int)hv_geometry_leaf_count(g) : 0;
        printf("%s = %s %s %s: %llu voxels, %d materials, shape from %d recorded mesh%s\n", c->output, pa, opname, pb,
               (unsigned long long)hv_object_voxels(h), hv_material_count(ta), leaves, leaves == 1 ? "" : "es");
        hv_geometry_destroy(g);
    }
    hv_volume_destroy(out);
    hv_object_destroy(h);
    hv_object_destroy(a);
    hv_object_destroy(b);
    hv_material_table_destroy(ta);
    hv_material_table_destroy(tb);
    hv_volume_destroy(va);
    hv_volume_destroy(vb);
    return s == HV_OK ? EXIT_OK : cli_fail(s);
}

const cli_spec cmd_boolean = {
    "boolean", "heterogeneous Booleans of two graded models (Wu eq. 27-30, CSG subtract)",
    "A.vdb OP B.vdb -o C.vdb        OP: intersect, union, difference, merge, subtract",
    "Combines two graded models on the same voxel lattice (voxelize with the same --voxel-size, or\n"
    "--like) and the same materials. What each does to the shape and to the material:\n"
    "  intersect   A n B; the overlap takes both models' sources (Wu eq. 27)\n"
    "  union       A u B; A alone keeps A's material, B alone B's, the overlap both (eq. 28)\n"
    "  difference  A's shape; the overlap takes B's material, the rest A's (Wu's, eq. 29)\n"
    "  merge       A u B as one region graded by both models' sources together (eq. 30)\n"
    "  subtract    A - B, A's material (CSG: a hole where B was)\n"
    "The result's voxels and its recorded shape change together: it records both models' meshes\n"
    "and the Boolean, so layers, tray and export cut the exact shape (issue 28). The result is\n"
    "the same model, byte for byte, as Lua's a:intersect(b), a:union(b), ... saved.\n",
    NULL, &k_local,
    "A model without materials, models on different lattices or with different materials, and a\n"
    "damaged recorded shape are refused (exit 1) naming the model and the operation; nothing is\n"
    "written.\n",
    3, 3, "A.vdb OP B.vdb arguments", CLI_THREADS | CLI_QUIET | CLI_POS_FILES, run, NULL, NULL};
