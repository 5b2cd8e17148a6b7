/* tests/material/test_regions.c - objects from assemblies (hovox/material.h): named regions with
 * bases of their own from the bodies' materials, grading without sources (fractions exactly 1 and
 * 0 per region), a source restricted to one region, the material list given or built, the
 * definition through a .vdb (schema 2), Booleans keeping names and bases, and the refusals. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"
#include "support/support.h"

static hv_mesh *box(double lo, double hi)
{
    hv_mesh *m = NULL;
    double a[3] = {lo, lo, lo}, b[3] = {hi, hi, hi};
    cr_assert_eq(hv_generate_box(a, b, &m), HV_OK, "%s", hv_last_error());
    return m;
}

/* Two nested boxes, the core (Agilus) first, voxelized at 0.5 mm. */
static hv_volume *nested(const char *core_mat, const char *shell_mat, int shell_first)
{
    hv_mesh *outer = box(0, 10), *inner = box(3, 7), *j = NULL;
    hv_mesh_part core = {inner, "core", core_mat}, shell = {outer, "shell", shell_mat};
    hv_mesh_part parts[2] = {shell_first ? shell : core, shell_first ? core : shell};
    cr_assert_eq(hv_mesh_join(parts, 2, &j), HV_OK, "%s", hv_last_error());
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.5;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(j, &o, &v), HV_OK, "%s", hv_last_error());
    hv_mesh_destroy(j);
    hv_mesh_destroy(inner);
    hv_mesh_destroy(outer);
    return v;
}

static int grid(const hv_volume *v, const char *name)
{
    int g = hv_volume_grid_find(v, name);
    cr_assert(g >= 0, "no grid %s", name);
    return g;
}

/* Over every occupied voxel of graded model g: the voxels of bool grid `region` of model v
 * must hold exactly `want` (m fractions); returns how many were checked. */
static uint64_t expect_exact(const hv_volume *g, const hv_material_table *t, const hv_volume *v, const char *region,
                             const double *want)
{
    int gr = grid(v, region), m = hv_material_count(t), gm[8];
    for (int j = 0; j < m; ++j) gm[j] = hv_material_grid(g, t, j);
    hv_accessor acc, ag;
    hv_accessor_init(&acc, v);
    hv_accessor_init(&ag, g);
    uint64_t n = 0;
    const int32_t *org = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
        for (unsigned q = 0; q < 512; ++q) {
            if (!HV_BIT_GET(hv_volume_leaf_bool_c(v, gr, l), q) || !HV_BIT_GET(hv_volume_leaf_mask(v, l), q)) continue;
            int32_t x = org[3 * l] + (int32_t)(q >> 6), y = org[3 * l + 1] + (int32_t)((q >> 3) & 7),
                    z = org[3 * l + 2] + (int32_t)(q & 7);
            cr_assert(hv_accessor_active(&ag, x, y, z));
            for (int j = 0; j < m; ++j) {
                float f = hv_accessor_float(&ag, gm[j], x, y, z);
                if (want[j] >= 0) cr_assert_eq(f, (float)want[j], "%s (%d,%d,%d) %s = %.9g", region, x, y, z,
                                               hv_material_name(t, j), (double)f);
            }
            ++n;
        }
    return n;
}

Test(regions, an_assembly_grades_to_its_bodies_materials_without_sources)
{
    hv_volume *v = nested("Agilus", "Vero", 0);
    hv_material_table *t = NULL;
    hv_object *o = NULL;
    cr_assert_eq(hv_object_from_regions(v, NULL, &t, &o), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_material_count(t), 2);
    cr_assert_str_eq(hv_material_name(t, 0), "Agilus");
    cr_assert_str_eq(hv_material_name(t, 1), "Vero");
    cr_assert_eq(hv_object_region_count(o), 2);
    cr_assert_str_eq(hv_object_region_name(o, 0), "core");
    cr_assert_str_eq(hv_object_region_name(o, 1), "shell");
    cr_assert_eq(hv_object_region_find(o, "shell"), 1);
    double b[2];
    hv_object_region_base(o, 0, b);
    cr_assert(b[0] == 1 && b[1] == 0);
    hv_object_region_base(o, 1, b);
    cr_assert(b[0] == 0 && b[1] == 1);
    cr_assert_eq(hv_object_voxels(o), hv_volume_mask_count(v, grid(v, "occupancy")));
    hv_volume *g = NULL;
    cr_assert_eq(hv_object_evaluate(o, t, 0, NULL, &g), HV_OK, "%s", hv_last_error());
    const double agilus[2] = {1, 0}, vero[2] = {0, 1};
    uint64_t nc = expect_exact(g, t, v, "region.core", agilus), ns = expect_exact(g, t, v, "region.shell", vero);
    cr_assert(nc > 0 && ns > nc);
    cr_assert_eq(nc + ns, hv_volume_mask_count(g, grid(g, "occupancy")));
    /* the graded model keeps the regions and the assembly's record */
    cr_assert_eq(hv_volume_mask_count(g, grid(g, "region.core")), nc);
    cr_assert_not_null(hv_volume_meta_string(g, "hovox.regions.json"));
    cr_assert(strncmp(hv_volume_meta_string(g, "hovox.object.json"), "{\"schema\": 2, ", 14) == 0);
    /* direct evaluation gives the bases too */
    hv_transform xf = hv_volume_get_transform(v);
    double p[3] = {5, 5, 5}, q[3] = {1, 1, 1}, f[2];
    int inside;
    cr_assert_eq(hv_object_prepare(o, NULL), HV_OK);
    hv_object_sample(o, p, &inside, f);
    cr_assert(inside && f[0] == 1 && f[1] == 0);
    hv_object_sample(o, q, &inside, f);
    cr_assert(inside && f[0] == 0 && f[1] == 1);
    (void)xf;
    hv_volume_destroy(g);
    hv_object_destroy(o);
    hv_material_table_destroy(t);
    hv_volume_destroy(v);
}

Test(regions, a_source_added_to_one_region_leaves_the_others_at_their_base)
{
    hv_volume *v = nested("Agilus", "Vero", 0);
    hv_material_table *t = NULL;
    hv_object *o = NULL;
    cr_assert_eq(hv_object_from_regions(v, NULL, &t, &o), HV_OK, "%s", hv_last_error());
    double c[3] = {5, 5, 5}, ms[2] = {0, 1}, me[2] = {1, 0};
    hv_frf *pt = NULL;
    cr_assert_eq(hv_frf_point(c, &pt), HV_OK);
    hv_ags_desc d = {pt, 0, 3, 0, NULL, ms, me, 2, "radial"};
    hv_dfn *fn = NULL;
    cr_assert_eq(hv_dfn_expr("d/dg", &fn), HV_OK);
    d.f = fn;
    hv_ags *a = NULL;
    cr_assert_eq(hv_ags_create(&d, &a), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_add_ags_region(o, "core", a), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_region_ags_count(o, 0), 1);
    cr_assert_eq(hv_object_region_ags_count(o, 1), 0);
    cr_assert_eq(hv_object_add_ags_region(o, "Core", a), HV_ERR_NOT_FOUND);
    cr_assert_str_eq(hv_last_error(), "the object has no region 'Core' (regions: core, shell)");
    hv_volume *g = NULL;
    cr_assert_eq(hv_object_evaluate(o, t, 0, NULL, &g), HV_OK, "%s", hv_last_error());
    const double vero[2] = {0, 1};
    expect_exact(g, t, v, "region.shell", vero);
    /* the core follows the source: Agilus grows with the distance from the centre */
    hv_accessor acc;
    hv_accessor_init(&acc, g);
    int ga = hv_material_grid(g, t, 0);
    double idx[3];
    hv_volume_world_to_index(g, c, idx);
    int32_t i0 = (int32_t)lround(idx[0]), j0 = (int32_t)lround(idx[1]), k0 = (int32_t)lround(idx[2]);
    float centre = hv_accessor_float(&acc, ga, i0, j0, k0), off = hv_accessor_float(&acc, ga, i0 + 3, j0, k0);
    cr_assert(centre < 0.2f && off > centre + 0.3f, "centre %g, 1.5 mm out %g", (double)centre, (double)off);
    /* through a file: names, bases, the source in its region */
    const char *path = t_tmpfile("regions_graded.vdb");
    cr_assert_eq(hv_volume_save(g, path), HV_OK, "%s", hv_last_error());
    hv_volume *w = NULL;
    cr_assert_eq(hv_volume_load(path, &w), HV_OK, "%s", hv_last_error());
    hv_object *r = NULL;
    cr_assert_eq(hv_object_from_model(w, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_region_count(r), 2);
    cr_assert_str_eq(hv_object_region_name(r, 0), "core");
    cr_assert_str_eq(hv_object_region_name(r, 1), "shell");
    cr_assert_eq(hv_object_region_ags_count(r, 0), 1);
    cr_assert_eq(hv_object_region_ags_count(r, 1), 0);
    double b[2];
    hv_object_region_base(r, 1, b);
    cr_assert(b[0] == 0 && b[1] == 1);
    hv_object_region_base(r, 0, b);
    cr_assert(b[0] == 1 && b[1] == 0);
    hv_volume *g2 = NULL;
    cr_assert_eq(hv_object_evaluate(r, t, 0, NULL, &g2), HV_OK, "%s", hv_last_error());
    hv_accessor a2;
    hv_accessor_init(&a2, g2);
    const int32_t *org = hv_volume_leaf_origins(g);
    for (size_t l = 0; l < hv_volume_leaf_count(g); ++l)
        for (unsigned q = 0; q < 512; ++q) {
            if (!HV_BIT_GET(hv_volume_leaf_mask(g, l), q)) continue;
            int32_t x = org[3 * l] + (int32_t)(q >> 6), y = org[3 * l + 1] + (int32_t)((q >> 3) & 7),
                    z = org[3 * l + 2] + (int32_t)(q & 7);
            for (int j = 0; j < 2; ++j)
                cr_assert_eq(hv_accessor_float(&acc, hv_material_grid(g, t, j), x, y, z),
                             hv_accessor_float(&a2, hv_material_grid(g2, t, j), x, y, z));
        }
    cr_assert_str_eq(hv_volume_meta_string(g2, "hovox.object.json"), hv_volume_meta_string(g, "hovox.object.json"));
    hv_volume_destroy(g2);
    hv_object_destroy(r);
    hv_volume_destroy(w);
    hv_volume_destroy(g);
    hv_ags_release(a);
    hv_dfn_destroy(fn);
    hv_frf_release(pt);
    hv_object_destroy(o);
    hv_material_table_destroy(t);
    hv_volume_destroy(v);
}

Test(regions, a_given_material_list_orders_the_table_and_must_name_every_region)
{
    hv_volume *v = nested("Agilus30 Clear", "Vero", 0);
    hv_material_table *given = NULL, *t = NULL;
    cr_assert_eq(hv_material_table_parse("Vero,Support,Agilus30_Clear", NULL, NULL, 0, &given), HV_OK);
    hv_object *o = NULL;
    cr_assert_eq(hv_object_from_regions(v, given, &t, &o), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_material_count(t), 3);
    cr_assert_str_eq(hv_material_name(t, 0), "Vero");
    double b[3];
    hv_object_region_base(o, 0, b); /* core: Agilus30 Clear -> Agilus30_Clear, the third */
    cr_assert(b[0] == 0 && b[1] == 0 && b[2] == 1);
    hv_object_region_base(o, 1, b);
    cr_assert(b[0] == 1 && b[1] == 0 && b[2] == 0);
    hv_object_destroy(o);
    hv_material_table_destroy(t);
    hv_material_table_destroy(given);
    cr_assert_eq(hv_material_table_parse("Vero,Agilus", NULL, NULL, 0, &given), HV_OK);
    t = (hv_material_table *)1;
    cr_assert_eq(hv_object_from_regions(v, given, &t, &o), HV_ERR_INVALID);
    cr_assert_null(o);
    cr_assert_null(t);
    cr_assert_str_eq(hv_last_error(), "region 'core' is material Agilus30_Clear (in the file: Agilus30 Clear), which "
                                      "the materials given (Vero, Agilus) do not name");
    hv_material_table_destroy(given);
    /* without a list the names are made valid */
    cr_assert_eq(hv_object_from_regions(v, NULL, &t, &o), HV_OK, "%s", hv_last_error());
    cr_assert_str_eq(hv_material_name(t, 0), "Agilus30_Clear");
    hv_object_destroy(o);
    hv_material_table_destroy(t);
    hv_volume_destroy(v);
}

Test(regions, regions_without_materials_need_a_list_and_empty_regions_are_left_out)
{
    hv_volume *v = nested(NULL, "Vero", 0);
    hv_material_table *t = NULL, *given = NULL;
    hv_object *o = NULL;
    cr_assert_eq(hv_object_from_regions(v, NULL, &t, &o), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "region 'core' has no material"), "%s", hv_last_error());
    cr_assert_eq(hv_material_table_parse("Vero,Clear", NULL, NULL, 0, &given), HV_OK);
    cr_assert_eq(hv_object_from_regions(v, given, &t, &o), HV_OK, "%s", hv_last_error());
    double b[2];
    hv_object_region_base(o, 0, b); /* no material: the first */
    cr_assert(b[0] == 1 && b[1] == 0);
    hv_object_destroy(o);
    hv_material_table_destroy(t);
    hv_material_table_destroy(given);
    hv_volume_destroy(v);
    /* shell first: the core lost every voxel and is not a region of the object */
    v = nested("Agilus", "Vero", 1);
    cr_assert_eq(hv_object_from_regions(v, NULL, &t, &o), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_material_count(t), 2); /* its material is still in the table */
    cr_assert_eq(hv_object_region_count(o), 1);
    cr_assert_str_eq(hv_object_region_name(o, 0), "shell");
    cr_assert_eq(hv_object_region_find(o, "core"), -1);
    hv_object_destroy(o);
    hv_material_table_destroy(t);
    hv_volume_destroy(v);
    /* not an assembly */
    hv_mesh *m = box(0, 4);
    hv_voxelize_options opt;
    hv_voxelize_options_init(&opt);
    cr_assert_eq(hv_voxelize(m, &opt, &v), HV_OK);
    cr_assert_eq(hv_object_from_regions(v, NULL, &t, &o), HV_ERR_NOT_FOUND);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}

Test(regions, booleans_keep_names_and_bases)
{
    hv_volume *v = nested("Agilus", "Vero", 0);
    hv_material_table *t = NULL;
    hv_object *a = NULL, *b = NULL, *r = NULL;
    cr_assert_eq(hv_object_from_regions(v, NULL, &t, &a), HV_OK, "%s", hv_last_error());
    /* b: the lower half of the model, one unnamed region with base Vero */
    hv_transform xf = hv_volume_get_transform(v);
    hv_volume *half = NULL;
    cr_assert_eq(hv_volume_create(&xf, &half), HV_OK);
    int lo[3] = {-4, -4, -4}, hi[3] = {24, 24, 9};
    cr_assert_eq(t_add_box(half, lo, hi), HV_OK);
    int g;
    cr_assert_eq(hv_volume_grid_add(half, "occupancy", HV_GRID_BOOL, &g), HV_OK);
    for (size_t l = 0; l < hv_volume_leaf_count(half); ++l)
        memcpy(hv_volume_leaf_bool(half, g, l), hv_volume_leaf_mask(half, l), 64);
    cr_assert_eq(hv_object_create(half, "occupancy", 2, &b), HV_OK, "%s", hv_last_error());
    double vero[2] = {0, 1};
    cr_assert_eq(hv_object_set_base(b, vero), HV_OK);
    cr_assert_eq(hv_object_boolean(a, b, HV_OP_INTERSECT, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_region_count(r), 2);
    cr_assert_str_eq(hv_object_region_name(r, 0), "core");
    cr_assert_str_eq(hv_object_region_name(r, 1), "shell");
    double p[2];
    hv_object_region_base(r, 0, p);
    cr_assert(p[0] == 1 && p[1] == 0);
    hv_object_destroy(r);
    /* union: the pieces of a keep the names; b's piece outside a is unnamed with b's base */
    cr_assert_eq(hv_object_boolean(a, b, HV_OP_UNITE, &r), HV_OK, "%s", hv_last_error());
    int unnamed = 0;
    for (int i = 0; i < hv_object_region_count(r); ++i) {
        if (hv_object_region_name(r, i)) continue;
        ++unnamed;
        hv_object_region_base(r, i, p);
    }
    cr_assert(unnamed >= 1);
    cr_assert_eq(hv_object_region_find(r, "core"), 0);
    hv_volume *gv = NULL;
    cr_assert_eq(hv_object_evaluate(r, t, 0, NULL, &gv), HV_OK, "%s", hv_last_error());
    cr_assert_geq(hv_volume_grid_find(gv, "region.core"), 0);
    cr_assert_geq(hv_volume_grid_find(gv, "region.shell"), 0);
    hv_object *back = NULL;
    cr_assert_eq(hv_object_from_model(gv, &back), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_region_count(back), hv_object_region_count(r));
    for (int i = 0; i < hv_object_region_count(r); ++i) {
        const char *n1 = hv_object_region_name(r, i), *n2 = hv_object_region_name(back, i);
        cr_assert((!n1 && !n2) || (n1 && n2 && strcmp(n1, n2) == 0));
        double q1[2], q2[2];
        hv_object_region_base(r, i, q1);
        hv_object_region_base(back, i, q2);
        cr_assert(q1[0] == q2[0] && q1[1] == q2[1]);
    }
    hv_object_destroy(back);
    hv_volume_destroy(gv);
    hv_object_destroy(r);
    /* set_base reaches every region */
    double half_half[2] = {0.5, 0.5};
    cr_assert_eq(hv_object_set_base(a, half_half), HV_OK);
    hv_object_region_base(a, 1, p);
    cr_assert(p[0] == 0.5 && p[1] == 0.5);
    cr_assert_eq(hv_object_set_region_base(a, 1, vero), HV_OK);
    double bad[2] = {0.5, 0.6};
    cr_assert_eq(hv_object_set_region_base(a, 0, bad), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "region 'core'"), "%s", hv_last_error());
    cr_assert_eq(hv_object_set_region_base(a, 2, vero), HV_ERR_INVALID);
    hv_object_destroy(a);
    hv_object_destroy(b);
    hv_volume_destroy(half);
    hv_material_table_destroy(t);
    hv_volume_destroy(v);
}

Test(regions, older_single_region_definitions_keep_schema_1)
{
    hv_mesh *m = box(0, 4);
    hv_voxelize_options opt;
    hv_voxelize_options_init(&opt);
    hv_volume *v = NULL, *g = NULL;
    cr_assert_eq(hv_voxelize(m, &opt, &v), HV_OK);
    hv_object *o = NULL;
    cr_assert_eq(hv_object_create(v, "occupancy", 2, &o), HV_OK);
    hv_material_table *t = NULL;
    cr_assert_eq(hv_material_table_parse("A,B", NULL, NULL, 0, &t), HV_OK);
    cr_assert_eq(hv_object_evaluate(o, t, 0, NULL, &g), HV_OK, "%s", hv_last_error());
    const char *doc = hv_volume_meta_string(g, "hovox.object.json");
    cr_assert(strncmp(doc, "{\"schema\": 1, ", 14) == 0, "%s", doc);
    cr_assert_null(strstr(doc, "\"name\""));
    cr_assert_eq(hv_volume_grid_count(g), 4); /* occupancy, 2 materials, surface: no region grid */
    hv_volume_destroy(g);
    hv_material_table_destroy(t);
    hv_object_destroy(o);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}
