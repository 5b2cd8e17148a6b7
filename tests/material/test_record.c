/* tests/material/test_record.c - a graded model carries its model's record (metadata other than
 * the grading documents, the "surface" grid restricted to the graded voxels), whichever front
 * end graded it: one definition graded through the C path `hovox grade` takes, through the Lua
 * binding (luaL_dostring over the hovox module) and, when built, by the hovox binary itself
 * gives the same grids (names, types, active voxels, values) and the same metadata. */
#include <criterion/criterion.h>
#include <lauxlib.h>
#include <lualib.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"
#include "lua/lhovox.h"
#include "support/support.h"

/* The definition, three ways. */
#define COLORS "#ff0000,#1f77b4"
static const char *LUA_SCRIPT =
    "local m = hovox.load(MODEL)\n"
    "local mats = hovox.materials{{name = 'A', color = '#ff0000', density = 1180}, {name = 'B', color = '#1f77b4'}}\n"
    "local o = hovox.object(m, mats)\n"
    "o:add_ags{feature = hovox.point{2, 2, 2}, d_grad = 3, f = 'd/dg', ms = {1, 0}, me = {0, 1}}\n"
    "o:add_ags{feature = m:contour(), d_neg = 0.5, d_grad = 1, f = '(d/dg)^2', ms = {0, 1}, me = {1, 0}}\n"
    "o:set_blend('idw', 2)\n"
    "o:evaluate():save(OUT)\n";
static const char *CLI_ARGS = "--materials A,B --colors '" COLORS "' --property A:density=1180 "
                              "--frf point:2,2,2 --ranges 0,3,0 --f d/dg --ms 1,0 --me 0,1 "
                              "--frf contour --ranges 0.5,1,0 --f '(d/dg)^2' --ms 0,1 --me 1,0 --blend idw";

static const char *make_model(void)
{
    double c[3] = {4, 4, 4};
    hv_mesh *mesh = NULL;
    cr_assert_eq(hv_generate_sphere(c, 3, 24, 12, &mesh), HV_OK);
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.5;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(mesh, &o, &v), HV_OK, "%s", hv_last_error());
    const char *path = t_tmpfile("model.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK, "%s", hv_last_error());
    hv_volume_destroy(v);
    hv_mesh_destroy(mesh);
    return path;
}

/* What cmd_grade does between reading its options and saving. */
static void grade_c(const char *model, const char *out)
{
    hv_material_table *t;
    cr_assert_eq(hv_material_table_create(&t), HV_OK);
    float a[4], b[4];
    cr_assert_eq(hv_color_parse("#ff0000", a), HV_OK);
    cr_assert_eq(hv_color_parse("#1f77b4", b), HV_OK);
    cr_assert_eq(hv_material_add(t, "A", a, NULL), HV_OK);
    cr_assert_eq(hv_material_add(t, "B", b, NULL), HV_OK);
    cr_assert_eq(hv_material_set_property(t, 0, "density", 1180, hv_property_si_unit("density")), HV_OK);
    hv_volume *vol;
    cr_assert_eq(hv_volume_load(model, &vol), HV_OK, "%s", hv_last_error());
    hv_object *o;
    cr_assert_eq(hv_object_create(vol, "occupancy", 2, &o), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_set_blend(o, HV_BLEND_IDW, 2.0), HV_OK);
    double p[3] = {2, 2, 2}, s1[2] = {1, 0}, s2[2] = {0, 1};
    hv_frf *f[2];
    cr_assert_eq(hv_frf_point(p, &f[0]), HV_OK);
    cr_assert_eq(hv_frf_contour(vol, "occupancy", &f[1]), HV_OK);
    const char *expr[2] = {"d/dg", "(d/dg)^2"};
    double ranges[2][3] = {{0, 3, 0}, {0.5, 1, 0}};
    for (int i = 0; i < 2; ++i) {
        hv_dfn *fn;
        cr_assert_eq(hv_dfn_expr(expr[i], &fn), HV_OK);
        hv_ags_desc d = {f[i], ranges[i][0], ranges[i][1], ranges[i][2], fn, i ? s2 : s1, i ? s1 : s2, 2, NULL};
        hv_ags *ags;
        cr_assert_eq(hv_ags_create(&d, &ags), HV_OK, "%s", hv_last_error());
        cr_assert_eq(hv_object_add_ags(o, ags), HV_OK);
        hv_ags_release(ags);
        hv_dfn_destroy(fn);
        hv_frf_release(f[i]);
    }
    hv_volume *g;
    cr_assert_eq(hv_object_evaluate(o, t, 0, NULL, &g), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_save(g, out), HV_OK, "%s", hv_last_error());
    hv_volume_destroy(g);
    hv_object_destroy(o);
    hv_volume_destroy(vol);
    hv_material_table_destroy(t);
}

static void grade_lua(const char *model, const char *out)
{
    lua_State *L = luaL_newstate();
    luaL_openlibs(L);
    luaL_requiref(L, "hovox", luaopen_hovox, 1);
    lua_pop(L, 1);
    lua_pushstring(L, model);
    lua_setglobal(L, "MODEL");
    lua_pushstring(L, out);
    lua_setglobal(L, "OUT");
    int rc = luaL_dostring(L, LUA_SCRIPT);
    cr_assert_eq(rc, LUA_OK, "%s", lua_tostring(L, -1));
    lua_close(L);
}

static void expect_same_models(const char *pa, const char *pb)
{
    hv_volume *a, *b;
    cr_assert_eq(hv_volume_load(pa, &a), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_load(pb, &b), HV_OK, "%s", hv_last_error());
    hv_transform xa = hv_volume_get_transform(a), xb = hv_volume_get_transform(b);
    cr_assert(hv_transform_same(&xa, &xb));
    cr_assert_eq(hv_volume_active_count(a), hv_volume_active_count(b));
    cr_assert_eq(hv_volume_grid_count(a), hv_volume_grid_count(b));
    hv_accessor ab;
    hv_accessor_init(&ab, b);
    for (int g = 0; g < hv_volume_grid_count(a); ++g) {
        const char *name = hv_volume_grid_name(a, g);
        int h = hv_volume_grid_find(b, name);
        cr_assert_geq(h, 0, "%s: no grid %s", pb, name);
        cr_assert_eq(hv_volume_grid_type(a, g), hv_volume_grid_type(b, h), "%s", name);
        int is_bool = hv_volume_grid_type(a, g) == HV_GRID_BOOL;
        if (is_bool) cr_assert_eq(hv_volume_mask_count(a, g), hv_volume_mask_count(b, h), "%s", name);
        const int32_t *org = hv_volume_leaf_origins(a);
        for (size_t l = 0; l < hv_volume_leaf_count(a); ++l)
            for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
                if (!HV_BIT_GET(hv_volume_leaf_mask(a, l), n)) continue;
                int32_t i = org[3 * l] + (int32_t)(n >> 6), j = org[3 * l + 1] + (int32_t)((n >> 3) & 7),
                        k = org[3 * l + 2] + (int32_t)(n & 7);
                cr_assert(hv_accessor_active(&ab, i, j, k));
                if (is_bool)
                    cr_assert_eq((int)HV_BIT_GET(hv_volume_leaf_bool_c(a, g, l), n), hv_accessor_bool(&ab, h, i, j, k),
                                 "%s at (%d, %d, %d)", name, i, j, k);
                else
                    cr_assert_eq(hv_volume_leaf_float_c(a, g, l)[n], hv_accessor_float(&ab, h, i, j, k),
                                 "%s at (%d, %d, %d)", name, i, j, k);
            }
    }
    cr_assert_eq(hv_volume_meta_count(a), hv_volume_meta_count(b));
    for (int i = 0; i < hv_volume_meta_count(a); ++i) {
        const char *key = hv_volume_meta_key(a, i), *sa = hv_volume_meta_string(a, key), *sb = hv_volume_meta_string(b, key);
        double na, nb;
        if (sa)
            cr_assert(sb && strcmp(sa, sb) == 0, "metadata %s differs:\n%.200s\n%.200s", key, sa, sb ? sb : "(none)");
        else
            cr_assert(hv_volume_meta_number(a, key, &na) && hv_volume_meta_number(b, key, &nb) && na == nb, "%s", key);
    }
    hv_volume_destroy(a);
    hv_volume_destroy(b);
}

Test(record, graded_models_are_the_same_from_c_lua_and_the_cli, .timeout = 120)
{
    const char *model = make_model();
    char c_out[1024], lua_out[1024];
    snprintf(c_out, sizeof c_out, "%s", t_tmpfile("c.vdb"));
    snprintf(lua_out, sizeof lua_out, "%s", t_tmpfile("lua.vdb"));
    grade_c(model, c_out);
    grade_lua(model, lua_out);

    /* the record is there: the surface restricted to the graded voxels, the model's documents */
    hv_volume *g, *src;
    cr_assert_eq(hv_volume_load(lua_out, &g), HV_OK);
    cr_assert_eq(hv_volume_load(model, &src), HV_OK);
    int gs = hv_volume_grid_find(g, "surface");
    cr_assert_geq(gs, 0, "the Lua-graded model has no surface grid");
    cr_assert_eq(hv_volume_mask_count(g, gs), hv_volume_mask_count(src, hv_volume_grid_find(src, "surface")));
    cr_assert_eq(hv_volume_active_count(g), hv_volume_active_count(src));
    static const char *const kept[] = {"hovox.mesh.json", "hovox.voxelize.json", "hovox.version"};
    for (size_t i = 0; i < sizeof kept / sizeof kept[0]; ++i)
        cr_assert_str_eq(hv_volume_meta_string(g, kept[i]), hv_volume_meta_string(src, kept[i]));
    hv_voxelize_record rec;
    cr_assert_eq(hv_voxelize_record_read(g, &rec), HV_OK, "%s", hv_last_error());
    cr_assert_eq(rec.mesh.bbox_min[0], 1);
    hv_volume_destroy(g);
    hv_volume_destroy(src);

    expect_same_models(c_out, lua_out);

    const char *build = getenv("HOVOX_BUILD");
    char exe[1024], cmd[4096];
    snprintf(exe, sizeof exe, "%s/hovox", build ? build : "build");
    if (!t_exists(exe)) {
        cr_log_warn("%s not built: the binary's output is not compared", exe);
        return;
    }
    char cli_out[1024];
    snprintf(cli_out, sizeof cli_out, "%s", t_tmpfile("cli.vdb"));
    snprintf(cmd, sizeof cmd, "'%s' grade '%s' -o '%s' -q %s", exe, model, cli_out, CLI_ARGS);
    cr_assert_eq(t_run(cmd, NULL), 0, "%s", cmd);
    expect_same_models(c_out, cli_out);
}

/* Objects combined by Booleans keep what both operands' models record alike and the union of
 * their surfaces; an object rebuilt from a graded model keeps that model's record. */
Test(record, booleans_and_rebuilt_objects_keep_the_record, .timeout = 120)
{
    double lo1[3] = {0, 0, 0}, hi1[3] = {4, 4, 4}, lo2[3] = {2, 0, 0}, hi2[3] = {6, 4, 4};
    hv_mesh *m1, *m2;
    cr_assert_eq(hv_generate_box(lo1, hi1, &m1), HV_OK);
    cr_assert_eq(hv_generate_box(lo2, hi2, &m2), HV_OK);
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.5;
    hv_volume *v1, *v2;
    cr_assert_eq(hv_voxelize(m1, &o, &v1), HV_OK);
    cr_assert_eq(hv_voxelize(m2, &o, &v2), HV_OK);
    cr_assert_eq(hv_volume_meta_set_string(v1, "user.note", "same"), HV_OK);
    cr_assert_eq(hv_volume_meta_set_string(v2, "user.note", "same"), HV_OK);
    hv_material_table *t;
    cr_assert_eq(hv_material_table_create(&t), HV_OK);
    cr_assert_eq(hv_material_add(t, "A", NULL, NULL), HV_OK);
    hv_object *a, *b, *u;
    cr_assert_eq(hv_object_create(v1, "occupancy", 1, &a), HV_OK);
    cr_assert_eq(hv_object_create(v2, "occupancy", 1, &b), HV_OK);
    cr_assert_eq(hv_object_boolean(a, b, HV_OP_UNITE, &u), HV_OK, "%s", hv_last_error());
    hv_volume *g;
    cr_assert_eq(hv_object_evaluate(u, t, 0, NULL, &g), HV_OK, "%s", hv_last_error());
    /* the meshes differ: their reports are not the union's; what both record alike stays */
    cr_assert_null(hv_volume_meta_string(g, "hovox.mesh.json"));
    cr_assert_str_eq(hv_volume_meta_string(g, "user.note"), "same");
    cr_assert_null(hv_volume_meta_string(g, "hovox.voxelize.json"));
    int gs = hv_volume_grid_find(g, "surface");
    cr_assert_geq(gs, 0);
    uint64_t s1 = hv_volume_mask_count(v1, hv_volume_grid_find(v1, "surface")),
             s2 = hv_volume_mask_count(v2, hv_volume_grid_find(v2, "surface")), su = hv_volume_mask_count(g, gs);
    cr_assert(su > s1 && su > s2 && su <= s1 + s2, "surface of the union: %llu (%llu, %llu)", (unsigned long long)su,
              (unsigned long long)s1, (unsigned long long)s2);
    /* rebuilt from the graded model: the record comes along */
    hv_object *r;
    cr_assert_eq(hv_object_from_model(g, &r), HV_OK, "%s", hv_last_error());
    hv_volume *g2;
    cr_assert_eq(hv_object_evaluate(r, t, 0, NULL, &g2), HV_OK, "%s", hv_last_error());
    cr_assert_str_eq(hv_volume_meta_string(g2, "user.note"), "same");
    cr_assert_eq(hv_volume_mask_count(g2, hv_volume_grid_find(g2, "surface")), su);
    hv_volume_destroy(g2);
    hv_object_destroy(r);
    hv_volume_destroy(g);
    hv_object_destroy(u);
    hv_object_destroy(a);
    hv_object_destroy(b);
    hv_material_table_destroy(t);
    hv_volume_destroy(v1);
    hv_volume_destroy(v2);
    hv_mesh_destroy(m1);
    hv_mesh_destroy(m2);
}
