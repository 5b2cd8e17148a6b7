/* tests/slicing/test_mesh_layers.c - one step from a mesh to a stack (slicing/mesh_layers.c, issue
 * 27 item 2, issue 29 item 1): hv_layers_mesh_model's one rule (a coloured mesh painted in its
 * colours, an assembly in its bodies' materials, materials given winning over colour), its
 * refusals, and hv_layers_write_mesh (what Lua and Python call) writing the same files as the
 * CLI's steps (hv_layers_mesh_model, hv_layers_colour_hook, hv_layers_write) with the colour's
 * dE2000 in the manifest and in its report. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/colour.h"
#include "hovox/layers.h"
#include "hovox/material.h"
#include "support/support.h"

static void j750(hv_layers_options *o)
{
    hv_layers_options_init(o);
    o->profile = "j750";
    o->first = 20;
    o->last = 22;
}

/* The mean fraction of material `name` over the model's occupied voxels (-1: not in the table). */
static double mean_of(const hv_volume *v, const char *name)
{
    hv_material_table *t = NULL;
    cr_assert_eq(hv_material_table_load(v, &t), HV_OK, "%s", hv_last_error());
    int m = hv_material_find(t, name);
    double sum = 0;
    size_t n = 0;
    if (m >= 0) {
        int g = hv_material_grid(v, t, m), occ = hv_volume_grid_find(v, "occupancy");
        cr_assert(g >= 0 && occ >= 0);
        for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
            const float *f = hv_volume_leaf_float_c(v, g, l);
            const uint64_t *o = hv_volume_leaf_bool_c(v, occ, l);
            for (int i = 0; i < 512; ++i)
                if (o[i >> 6] >> (i & 63) & 1u) {
                    sum += f[i];
                    ++n;
                }
        }
    }
    hv_material_table_destroy(t);
    return m < 0 ? -1 : n ? sum / (double)n : 0;
}

Test(mesh_layers, a_coloured_mesh_is_painted_and_materials_win)
{
    hv_mesh *m = t_red_cube(6);
    hv_layers_options o;
    j750(&o);
    hv_volume *v = NULL;
    hv_layers_mesh_voxels vx;
    /* no options: the mesh prints in its colours, 1 mm deep, on voxels of half the depth */
    cr_assert_eq(hv_layers_mesh_model(m, &o, NULL, NULL, &v, &vx), HV_OK, "%s", hv_last_error());
    cr_assert(vx.painted && vx.depth == HV_COLOUR_DEPTH_DEFAULT && vx.size == 0.5 && !vx.coarsened, "%d %g %g",
              vx.painted, vx.depth, vx.size);
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_for_model(v, &map), HV_OK, "the model is painted: %s", hv_last_error());
    hv_colour_map_destroy(map);
    /* red over the default profile: half magenta, half yellow in the skin, the white resin beneath */
    double mg = mean_of(v, "VeroMagenta-V"), w = mean_of(v, "VeroPureWhite");
    cr_assert(mg > 0.2 && mg < 0.5 && w > 0.1, "magenta %g, white %g", mg, w);
    hv_volume_destroy(v);
    /* a colour core and a given depth: every voxel red, on voxels of a quarter mm */
    hv_layers_mesh_options mo;
    memset(&mo, 0, sizeof mo);
    mo.colour_depth = 0.5;
    mo.core = "#ff0000";
    cr_assert_eq(hv_layers_mesh_model(m, &o, &mo, NULL, &v, &vx), HV_OK, "%s", hv_last_error());
    cr_assert(vx.painted && vx.depth == 0.5 && vx.size == 0.25, "%g %g", vx.depth, vx.size);
    cr_assert_float_eq(mean_of(v, "VeroMagenta-V"), 0.5, 1e-3);
    cr_assert_float_eq(mean_of(v, "VeroPureWhite"), 0.0, 1e-6);
    hv_volume_destroy(v);
    /* the body given a material: printed in it, not painted */
    memset(&mo, 0, sizeof mo);
    mo.materials.n = 1;
    char pair[256];
    snprintf(pair, sizeof pair, "%s=VeroCyan-V", hv_mesh_body_at(m, 0)->name);
    mo.materials.pair[0] = pair;
    cr_assert_eq(hv_body_materials_apply(&mo.materials, m), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_layers_mesh_model(m, &o, &mo, NULL, &v, &vx), HV_OK, "%s", hv_last_error());
    cr_assert(!vx.painted && vx.depth == 0 && vx.size == 25.4 / 300, "%g", vx.size);
    cr_assert_float_eq(mean_of(v, "VeroCyan-V"), 1.0, 1e-6);
    cr_assert_eq(mean_of(v, "VeroMagenta-V"), -1);
    cr_assert_eq(hv_colour_map_for_model(v, &map), HV_ERR_NOT_FOUND);
    hv_volume_destroy(v);
    /* colour with materials: refused naming both, nothing made */
    mo.colour_depth = 1;
    v = (hv_volume *)1;
    cr_assert_eq(hv_layers_mesh_model(m, &o, &mo, NULL, &v, NULL), HV_ERR_INVALID);
    cr_assert_eq(v, NULL);
    cr_assert(strstr(hv_last_error(), "paints the mesh in its colours") && strstr(hv_last_error(), "materials"), "%s",
              hv_last_error());
    hv_mesh_destroy(m);
}

Test(mesh_layers, a_plain_mesh_is_not_painted_unless_asked)
{
    hv_mesh *m = t_cube_mesh(0, 4);
    hv_layers_options o;
    j750(&o);
    hv_volume *v = NULL;
    /* no colour and no material: the body needs one */
    cr_assert_neq(hv_layers_mesh_model(m, &o, NULL, NULL, &v, NULL), HV_OK);
    cr_assert(strstr(hv_last_error(), "material"), "%s", hv_last_error());
    cr_assert_eq(v, NULL);
    /* asked to paint a mesh without colour: the painter's refusal */
    hv_layers_mesh_options mo;
    memset(&mo, 0, sizeof mo);
    mo.colour_depth = 1;
    cr_assert_eq(hv_layers_mesh_model(m, &o, &mo, NULL, &v, NULL), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "no colour to paint"), "%s", hv_last_error());
    cr_assert_eq(v, NULL);
    /* a profile that is not ICC: the colour map's refusal */
    FILE *f = fopen(t_tmpfile("bad.icc"), "w");
    fputs("not a profile\n", f);
    fclose(f);
    hv_mesh *red = t_red_cube(4);
    mo.colour.icc = t_tmpfile("bad.icc");
    cr_assert_eq(hv_layers_mesh_model(red, &o, &mo, NULL, &v, NULL), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "not an ICC profile"), "%s", hv_last_error());
    cr_assert_eq(v, NULL);
    hv_mesh_destroy(red);
    hv_mesh_destroy(m);
}

static int same_file(const char *a, const char *b)
{
    size_t na = 0, nb = 0;
    char *x = t_slurp(a, &na), *y = t_slurp(b, &nb);
    int same = x && y && na == nb && memcmp(x, y, na) == 0;
    free(x);
    free(y);
    return same;
}

Test(mesh_layers, the_front_ends_step_writes_the_clis_files_with_the_colour, .timeout = 120)
{
    hv_mesh *m = t_red_cube(6);
    hv_layers_options o;
    j750(&o);
    o.mesh_name = o.model_name = "red.ply";
    /* the CLI's steps */
    hv_volume *v = NULL;
    cr_assert_eq(hv_layers_mesh_model(m, &o, NULL, NULL, &v, NULL), HV_OK, "%s", hv_last_error());
    hv_layers_options lo = o;
    hv_colour_skin sk;
    cr_assert_eq(hv_layers_colour_hook(&lo, v, &sk), HV_OK);
    cr_assert(sk.map && sk.model == v && lo.manifest == hv_colour_manifest_hook && lo.manifest_user == &sk);
    char a[1024], b[1024];
    snprintf(a, sizeof a, "%s/cli", t_tmpdir());
    snprintf(b, sizeof b, "%s/lib", t_tmpdir());
    hv_layers_report ra, rb;
    cr_assert_eq(hv_layers_write(m, v, a, &lo, NULL, &ra), HV_OK, "%s", hv_last_error());
    cr_assert(sk.has_achieved && sk.target.voxels > 0);
    hv_colour_map_destroy(sk.map);
    /* a model not painted: no hook */
    hv_layers_options plain = o;
    hv_volume *none = NULL;
    hv_transform xf = {{0.5, 0.5, 0.5}, {0, 0, 0}};
    cr_assert_eq(hv_volume_create(&xf, &none), HV_OK);
    hv_colour_skin sn;
    cr_assert_eq(hv_layers_colour_hook(&plain, none, &sn), HV_OK);
    cr_assert(!sn.map && !plain.manifest);
    cr_assert_eq(hv_layers_colour_hook(&plain, NULL, &sn), HV_OK);
    cr_assert(!sn.map && !plain.manifest);
    hv_volume_destroy(none);
    hv_volume_destroy(v);
    /* the front ends' step: the same files, the same figures */
    hv_colour_skin sb;
    hv_material_table *tb = NULL;
    cr_assert_eq(hv_layers_write_mesh(m, NULL, b, &o, NULL, &rb, &sb, &tb), HV_OK, "%s", hv_last_error());
    cr_assert(sb.map && !sb.model && sb.has_achieved);
    cr_assert(!sb.printer_voxels, "a painted model's voxels are skin voxels, its model gone or not");
    cr_assert(tb && hv_material_count(tb) == rb.materials && rb.materials == 6, "the stack's six resins");
    hv_material_table_destroy(tb);
    cr_assert_eq(sb.target.voxels, sk.target.voxels);
    cr_assert_float_eq(sb.achieved.mean_de2000, sk.achieved.mean_de2000, 1e-12);
    cr_assert_eq(ra.object_pixels, rb.object_pixels);
    hv_colour_map_destroy(sb.map);
    const char *files[] = {"manifest.json", "layer-00020.png", "layer-00021.png"};
    for (int k = 0; k < 3; ++k) {
        char fa[1100], fb[1100];
        snprintf(fa, sizeof fa, "%s/%s", a, files[k]);
        snprintf(fb, sizeof fb, "%s/%s", b, files[k]);
        cr_assert(same_file(fa, fb), "%s differs", files[k]);
    }
    char path[1100];
    snprintf(path, sizeof path, "%s/manifest.json", b);
    char *man = t_slurp(path, NULL);
    cr_assert(man && strstr(man, "\"colour\"") && strstr(man, "mean_de2000_achieved"), "%s", man ? man : "");
    free(man);
    hv_mesh_destroy(m);
}
