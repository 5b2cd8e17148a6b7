/* tests/colour/test_mesh_colour.c - a coloured mesh printed in one step (src/colour/mesh_colour.c):
 * the rule that says when a mesh prints in its colours (hv_colour_mesh_paints: colour of its own,
 * no body made of a 3MF material), the voxels painting takes (hv_colour_mesh_voxels) and the
 * painted model (hv_colour_mesh_model), the same as voxelize then hv_colour_paint_text, and an
 * assembly painted by body (hv_colour_mesh_bodies: colour groups painted, resins kept). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/colour.h"
#include "hovox/layers.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"
#include "support/support.h"

static const hv_colour_body_rule k_asked = {1, NULL, NULL}; /* colour asked for, the table's resins */

static hv_mesh *load(const char *path)
{
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_load(path, &m), HV_OK, "%s: %s", path, hv_last_error());
    return m;
}

Test(mesh_colour, which_meshes_print_in_their_colours)
{
    /* corner colours (as PLY vertex colours and 3MF colour groups give them): painted */
    hv_mesh *m = t_red_cube(4);
    cr_assert_eq(hv_colour_mesh_paints(m, NULL), 1);
    /* the same cube once its body is made of a material: printed in it */
    cr_assert_eq(hv_mesh_body_material_set(m, hv_mesh_body_at(m, 0)->name, "VeroWhite"), HV_OK);
    cr_assert_eq(hv_colour_mesh_paints(m, NULL), 0);
    hv_mesh_destroy(m);
    /* no colour at all */
    m = t_cube_mesh(0, 4);
    cr_assert_eq(hv_colour_mesh_paints(m, NULL), 0);
    hv_mesh_destroy(m);
    /* an OBJ whose MTL gives its materials colours (Kd): appearance, painted; the same OBJ
     * without its library: materials are names only, no colour */
    FILE *f = fopen(t_tmpfile("k.mtl"), "w");
    fputs("newmtl red\nKd 1 0 0\n", f);
    fclose(f);
    for (int with = 1; with >= 0; --with) {
        f = fopen(t_tmpfile("k.obj"), "w");
        fprintf(f, "mtllib %s\nv 0 0 0\nv 4 0 0\nv 0 4 0\nv 0 0 4\nusemtl red\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
                with ? "k.mtl" : "none.mtl");
        fclose(f);
        m = load(t_tmpfile("k.obj"));
        cr_assert_eq(hv_colour_mesh_paints(m, NULL), with);
        hv_mesh_destroy(m);
    }
    /* 3MF: a Vero shell over an Agilus core (base materials with display colours), and base
     * materials and composites with a colour group on one body: printed in their materials */
    char path[4096];
    snprintf(path, sizeof path, "%s/good/core_in_shell.3mf", t_shared());
    m = load(path);
    cr_assert_eq(hv_colour_mesh_paints(m, NULL), 0);
    hv_mesh_destroy(m);
    snprintf(path, sizeof path, "%s/good/composite_core.3mf", t_shared());
    m = load(path);
    cr_assert_neq(hv_mesh_corner_colours(m), NULL);
    cr_assert_eq(hv_colour_mesh_paints(m, NULL), 0);
    hv_mesh_destroy(m);
}

Test(mesh_colour, voxels_a_quarter_of_the_depth_within_the_budget)
{
    hv_mesh *m = t_red_cube(40); /* only planned */
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    hv_voxel_plan plan;
    /* coarser than the printer's pitch: half the depth */
    cr_assert_eq(hv_colour_mesh_voxels(m, 0.0847, 1.0, 1ull << 40, &o, &plan), HV_OK, "%s", hv_last_error());
    cr_assert_float_eq(o.voxel_size[0], 0.5, 1e-12);
    /* a shallow skin: the printer's pitch */
    cr_assert_eq(hv_colour_mesh_voxels(m, 0.0847, 0.1, 1ull << 40, &o, &plan), HV_OK, "%s", hv_last_error());
    cr_assert_float_eq(o.voxel_size[0], 0.0847, 1e-12);
    /* a smaller budget coarsens by 5/4 steps until the plan and the painting (112 bytes an
     * occupied voxel) fit */
    cr_assert_eq(hv_colour_mesh_voxels(m, 0.0847, 1.0, 1ull << 40, &o, &plan), HV_OK);
    double need = (double)plan.memory_bytes + 64000.0 / (0.5 * 0.5 * 0.5) * 112.0;
    cr_assert_eq(hv_colour_mesh_voxels(m, 0.0847, 1.0, (uint64_t)(0.6 * need), &o, &plan), HV_OK, "%s",
                 hv_last_error());
    double v = o.voxel_size[0];
    cr_assert_float_eq(v, 0.625, 1e-12);
    cr_assert_leq((double)plan.memory_bytes + 64000.0 / (v * v * v) * 112.0, 0.6 * need);
    cr_assert_eq(hv_colour_mesh_voxels(m, 0.0847, 1.0, 10, &o, &plan), HV_ERR_LIMIT);
    cr_assert_eq(hv_colour_mesh_voxels(m, 0, 1.0, 1u << 30, &o, &plan), HV_ERR_INVALID);
    hv_mesh_destroy(m);
}

Test(mesh_colour, the_model_is_voxelize_then_paint)
{
    hv_mesh *m = t_red_cube(4);
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.5;
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_create(NULL, &map), HV_OK);
    hv_volume *a = NULL, *b = NULL;
    cr_assert_eq(hv_colour_mesh_model(m, &o, map, 1.0, NULL, NULL, &a), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_voxelize(m, &o, &b), HV_OK);
    cr_assert_eq(hv_colour_paint_text(b, m, map, 1.0, NULL), HV_OK);
    hv_material_table *ta = NULL;
    cr_assert_eq(hv_material_table_load(a, &ta), HV_OK);
    cr_assert_eq(hv_material_count(ta), HV_COLOUR_SLOTS); /* the core is the white resin, one of six */
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
        int ga = hv_material_grid(a, ta, k), gb = hv_material_grid(b, ta, k);
        cr_assert(ga >= 0 && gb >= 0);
        for (size_t l = 0; l < hv_volume_leaf_count(a); ++l)
            cr_assert_eq(memcmp(hv_volume_leaf_float_c(a, ga, l), hv_volume_leaf_float_c(b, gb, l), 512 * sizeof(float)),
                         0);
    }
    /* a mesh without colour is refused, nothing made */
    hv_mesh *plain = t_cube_mesh(0, 4);
    hv_volume *c = (hv_volume *)1;
    cr_assert_eq(hv_colour_mesh_model(plain, &o, map, 1.0, NULL, &k_asked, &c), HV_ERR_BAD_INPUT);
    cr_assert_eq(c, NULL);
    hv_mesh_destroy(plain);
    hv_material_table_destroy(ta);
    hv_volume_destroy(a);
    hv_volume_destroy(b);
    hv_colour_map_destroy(map);
    hv_mesh_destroy(m);
}

/* The value of material `name` (or grid `name` when no material has it) at the voxel nearest a
 * world point; -1 when the model has neither. */
static double at(const hv_volume *v, const char *name, double x, double y, double z)
{
    hv_material_table *t = NULL;
    cr_assert_eq(hv_material_table_load(v, &t), HV_OK);
    int m = hv_material_find(t, name);
    int g = m >= 0 ? hv_material_grid(v, t, m) : hv_volume_grid_find(v, name);
    hv_material_table_destroy(t);
    if (g < 0) return -1;
    double w[3] = {x, y, z}, ix[3];
    hv_volume_world_to_index(v, w, ix);
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    return hv_accessor_float(&acc, g, (int32_t)lrint(ix[0]), (int32_t)lrint(ix[1]), (int32_t)lrint(ix[2]));
}

/* Issue 29 item 2: an assembly's bodies painted by body (tests/colour/colour_assembly.py, a
 * Python-written 3MF): a colour group's body takes its colour unasked, a base material that is a
 * resin of the table stays in it, one that is not ("PLA Blue") prints in its material unless
 * colour is asked for, then in its displaycolor; resins alone with colour asked: refused. */
Test(mesh_colour, an_assembly_is_painted_by_body, .timeout = 60)
{
    char cmd[4200];
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 tests/colour/colour_assembly.py %s", t_tmpdir());
    cr_assert_eq(t_run(cmd, NULL), 0, "%s", cmd);
    hv_mesh *m = load(t_tmpfile("badge.3mf")), *r = load(t_tmpfile("resins.3mf"));
    uint8_t p[3];
    cr_assert_eq(hv_colour_mesh_bodies(m, NULL, p), 1);
    cr_assert(!p[0] && p[1] && !p[2], "base, badge, grip: %d %d %d", p[0], p[1], p[2]);
    cr_assert_eq(hv_colour_mesh_bodies(m, &k_asked, p), 2);
    cr_assert(!p[0] && p[1] && p[2]);
    cr_assert_eq(hv_colour_mesh_paints(m, NULL), 1);
    cr_assert_eq(hv_colour_mesh_bodies(r, &k_asked, NULL), 0);
    cr_assert_eq(hv_colour_mesh_paints(r, NULL), 0);
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.5;
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_create(NULL, &map), HV_OK);
    float red[6], blue[6];
    hv_colour_map_fractions(map, (const uint8_t[4]){0xc0, 0x10, 0x10, 0xff}, red);
    hv_colour_map_fractions(map, (const uint8_t[4]){0x20, 0x50, 0xc0, 0xff}, blue);
    for (int asked = 0; asked <= 1; ++asked) {
        hv_volume *v = NULL;
        cr_assert_eq(hv_colour_mesh_model(m, &o, map, 1.0, NULL, asked ? &k_asked : NULL, &v), HV_OK, "%s", hv_last_error());
        /* the base: all Agilus30Black, no colour asked for there, even under the badge */
        cr_assert_float_eq(at(v, "Agilus30Black", 10.25, 10.25, 2.25), 1.0, 1e-6);
        cr_assert_float_eq(at(v, "Agilus30Black", 4.25, 10.25, 3.75), 1.0, 1e-6);
        cr_assert_float_eq(at(v, "VeroMagenta-V", 4.25, 10.25, 3.75), 0.0, 1e-6);
        cr_assert_float_eq(at(v, "colour.mask", 10.25, 10.25, 2.25), 0.0, 1e-6);
        /* the badge: its colour's fractions in the skin, the white resin beneath */
        cr_assert_float_eq(at(v, "VeroMagenta-V", 4.25, 10.25, 6.25), red[1], 1e-6);
        cr_assert_float_eq(at(v, "VeroCyan-V", 4.25, 10.25, 6.25), red[0], 1e-6);
        cr_assert_float_eq(at(v, "VeroPureWhite", 10.25, 10.25, 6.25), 1.0, 1e-6);
        /* the grip: its material, or asked, painted in its displaycolor over the white core */
        if (!asked) {
            cr_assert_float_eq(at(v, "PLA_Blue", 26.25, 10.25, 2.25), 1.0, 1e-6);
            cr_assert_float_eq(at(v, "PLA_Blue", 22.25, 10.25, 2.25), 1.0, 1e-6);
        } else {
            cr_assert_eq(at(v, "PLA_Blue", 26.25, 10.25, 2.25), -1);
            cr_assert_float_eq(at(v, "VeroCyan-V", 22.25, 10.25, 2.25), blue[0], 1e-6);
            cr_assert_float_eq(at(v, "VeroPureWhite", 26.25, 10.25, 2.25), 1.0, 1e-6);
        }
        /* more than six would take slots for nothing: the unused colour resins left (clear) */
        hv_material_table *t = NULL;
        cr_assert_eq(hv_material_table_load(v, &t), HV_OK);
        cr_assert_eq(hv_material_find(t, "VeroClear"), -1);
        cr_assert_eq(hv_material_count(t), asked ? 6 : 7);
        hv_material_table_destroy(t);
        hv_volume_destroy(v);
    }
    hv_volume *v = (hv_volume *)1;
    cr_assert_eq(hv_colour_mesh_model(r, &o, map, 1.0, NULL, &k_asked, &v), HV_ERR_BAD_INPUT);
    cr_assert_eq(v, NULL);
    cr_assert(strstr(hv_last_error(), "no body to paint in its colours: a is VeroCyan-V, b is Agilus30Black"), "%s",
              hv_last_error());
    hv_colour_map_destroy(map);
    hv_mesh_destroy(m);
    hv_mesh_destroy(r);
}

/* Every grid of two models the same, byte for byte (names, leaves, values). */
static void same_grids(const hv_volume *a, const hv_volume *b)
{
    cr_assert_eq(hv_volume_leaf_count(a), hv_volume_leaf_count(b));
    cr_assert_eq(hv_volume_grid_count(a), hv_volume_grid_count(b));
    for (int g = 0; g < hv_volume_grid_count(a); ++g) {
        const char *name = hv_volume_grid_name(a, g);
        int h = hv_volume_grid_find(b, name);
        cr_assert(h >= 0, "grid %s missing", name);
        for (size_t l = 0; l < hv_volume_leaf_count(a); ++l) {
            size_t n = hv_volume_grid_type(a, g) == HV_GRID_BOOL ? 8 * sizeof(uint64_t) : 512 * sizeof(float);
            const void *pa = hv_volume_grid_type(a, g) == HV_GRID_BOOL ? (const void *)hv_volume_leaf_bool_c(a, g, l)
                                                                       : (const void *)hv_volume_leaf_float_c(a, g, l);
            const void *pb = hv_volume_grid_type(b, h) == HV_GRID_BOOL ? (const void *)hv_volume_leaf_bool_c(b, h, l)
                                                                       : (const void *)hv_volume_leaf_float_c(b, h, l);
            cr_assert_eq(memcmp(pa, pb, n), 0, "grid %s leaf %zu differs", name, l);
        }
    }
    hv_material_table *ta = NULL, *tb = NULL;
    cr_assert_eq(hv_material_table_load(a, &ta), HV_OK);
    cr_assert_eq(hv_material_table_load(b, &tb), HV_OK);
    cr_assert_eq(hv_material_count(ta), hv_material_count(tb));
    for (int j = 0; j < hv_material_count(ta); ++j) cr_assert_str_eq(hv_material_name(ta, j), hv_material_name(tb, j));
    hv_material_table_destroy(ta);
    hv_material_table_destroy(tb);
}

/* Issue 29 item 2: `voxelize --colour-depth` and Lua model:paint (hv_colour_mesh_paint on a voxelized
 * model) follow the body rule of `layers MESH` (hv_layers_mesh_model with colour_depth): on the
 * same voxels every grid of the two models is the same; the plate stays Agilus30Black (it was
 * painted in its displaycolor before); a single coloured body is painted exactly as
 * hv_colour_paint_text paints it (today's bytes). */
Test(mesh_colour, paint_follows_the_body_rule_of_layers, .timeout = 60)
{
    char cmd[4200];
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 tests/colour/colour_assembly.py %s", t_tmpdir());
    cr_assert_eq(t_run(cmd, NULL), 0, "%s", cmd);
    hv_mesh *m = load(t_tmpfile("badge.3mf"));
    hv_layers_options lo;
    hv_layers_options_init(&lo);
    hv_layers_mesh_options mo;
    memset(&mo, 0, sizeof mo);
    mo.voxel_size = 0.5;
    mo.colour_depth = 1.0;
    hv_volume *a = NULL, *b = NULL;
    cr_assert_eq(hv_layers_mesh_model(m, &lo, &mo, NULL, &a, NULL), HV_OK, "%s", hv_last_error());
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.5;
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_create(NULL, &map), HV_OK);
    cr_assert_eq(hv_voxelize(m, &o, &b), HV_OK);
    cr_assert_eq(hv_colour_mesh_paint(b, m, map, 1.0, NULL, &k_asked), HV_OK, "%s", hv_last_error());
    same_grids(a, b);
    cr_assert_float_eq(at(b, "Agilus30Black", 10.25, 10.25, 2.25), 1.0, 1e-6);
    cr_assert_float_eq(at(b, "colour.mask", 1.25, 1.25, 0.25), 0.0, 1e-6); /* the plate's skin: no colour */
    hv_volume_destroy(a);
    hv_volume_destroy(b);
    hv_mesh_destroy(m);
    /* one coloured body: the bytes of hv_colour_paint_text */
    m = t_red_cube(4);
    cr_assert_eq(hv_voxelize(m, &o, &a), HV_OK);
    cr_assert_eq(hv_voxelize(m, &o, &b), HV_OK);
    cr_assert_eq(hv_colour_paint_text(a, m, map, 1.0, "Agilus30"), HV_OK);
    cr_assert_eq(hv_colour_mesh_paint(b, m, map, 1.0, "Agilus30", &k_asked), HV_OK, "%s", hv_last_error());
    same_grids(a, b);
    hv_volume_destroy(a);
    hv_volume_destroy(b);
    hv_mesh_destroy(m);
    hv_colour_map_destroy(map);
}

static int maps_pla_blue(void *user, const char *material)
{
    ++*(int *)user;
    return strcmp(material, "PLA_Blue") == 0; /* the name the material takes in a model */
}

/* Issue 29 item 1: the caller's resins (a tray's --resin PLA_Blue=RESIN) are resins for the rule:
 * asked for colour, the grip stays in its material (then mapped), only the badge is painted. */
Test(mesh_colour, a_mapped_material_is_a_resin, .timeout = 60)
{
    char cmd[4200];
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 tests/colour/colour_assembly.py %s", t_tmpdir());
    cr_assert_eq(t_run(cmd, NULL), 0, "%s", cmd);
    hv_mesh *m = load(t_tmpfile("badge.3mf"));
    int calls = 0;
    hv_colour_body_rule rule = {1, maps_pla_blue, &calls};
    uint8_t p[3];
    cr_assert_eq(hv_colour_mesh_bodies(m, &rule, p), 1);
    cr_assert(!p[0] && p[1] && !p[2], "base, badge, grip: %d %d %d", p[0], p[1], p[2]);
    cr_assert_eq(calls, 1); /* the grip's alone: Agilus30Black is the table's, the badge a colour */
    rule.asked = 0;
    cr_assert_eq(hv_colour_mesh_paints(m, &rule), 1);
    rule.asked = 1;
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.5;
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_create(NULL, &map), HV_OK);
    hv_volume *v = NULL;
    cr_assert_eq(hv_colour_mesh_model(m, &o, map, 1.0, NULL, &rule, &v), HV_OK, "%s", hv_last_error());
    cr_assert_float_eq(at(v, "PLA_Blue", 22.25, 10.25, 2.25), 1.0, 1e-6);
    cr_assert_float_eq(at(v, "colour.mask", 22.25, 10.25, 2.25), 0.0, 1e-6);
    hv_volume_destroy(v);
    /* a body the user coloured (voxelize --colour, Lua mesh:set_colour) is painted, resin or not */
    cr_assert_eq(hv_mesh_body_colour_set(m, "base", 0x2050c0ffu), HV_OK);
    cr_assert_eq(hv_colour_mesh_bodies(m, &rule, p), 2);
    cr_assert(p[0] && p[1] && !p[2]);
    hv_colour_map_destroy(map);
    hv_mesh_destroy(m);
}
