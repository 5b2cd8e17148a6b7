/* tests/colour/test_skin.c - what a painted model asked for (src/colour/skin.c): the colour map made
 * again from the model's record, and the skin's CIEDE2000: a cube painted in one colour has, at
 * every skin voxel, the dE2000 hovox colour gives that colour (mean = max = it), the core none;
 * fractions scaled as a halftone's bias would move it; the manifest hook adds the "colour" member. */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/colour.h"
#include "support/support.h"

/* the cube [0, 6]^3 in one colour, painted 1 mm deep over Agilus30 at 0.5 mm */
static hv_volume *painted(hv_mesh **mesh, uint32_t rgba) { return t_painted_cube(6, &rgba, 1, mesh); }

Test(skin, one_colour_everywhere_gives_its_own_de2000)
{
    hv_mesh *m = NULL;
    hv_volume *v = painted(&m, 0xC8C8B4FFu);
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_for_model(v, &map), HV_OK, "%s", hv_last_error());
    cr_assert_str_eq(hv_colour_map_icc(map), hv_colour_default_icc());
    cr_assert_eq(hv_colour_map_intent(map), HV_INTENT_PERCEPTUAL);
    const uint8_t rgba[4] = {0xC8, 0xC8, 0xB4, 255};
    float f[HV_COLOUR_SLOTS];
    hv_colour_map_fractions(map, rgba, f);
    double want[3], got[3];
    hv_colour_map_lab_of_srgb(map, rgba, want);
    hv_colour_map_lab_of_fractions(map, f, got);
    double de = hv_colour_delta_e2000(want, got);
    hv_colour_skin_report r;
    cr_assert_eq(hv_colour_skin_error(v, map, NULL, &r), HV_OK, "%s", hv_last_error());
    cr_assert_gt(r.voxels, 500);
    cr_assert(fabs(r.mean_de2000 - de) < 1e-3 && fabs(r.max_de2000 - de) < 1e-3, "mean %g max %g, want %g",
              r.mean_de2000, r.max_de2000, de);
    /* the skin is every occupied voxel but the 8^3 whose centres (1.25 .. 4.75) lie deeper than 1 mm */
    uint64_t occupied = hv_volume_mask_count(v, hv_volume_grid_find(v, "occupancy"));
    cr_assert_eq(r.voxels, occupied - 8 * 8 * 8, "%llu skin voxels of %llu", (unsigned long long)r.voxels,
                 (unsigned long long)occupied);
    /* twice the black a halftone would print: further from the colour */
    double scale[HV_COLOUR_SLOTS] = {1, 1, 1, 1, 1, 1};
    cr_assert_gt(f[HV_COLOUR_Y], 0.1f);
    scale[HV_COLOUR_Y] = 2;
    hv_colour_skin_report r2;
    cr_assert_eq(hv_colour_skin_error(v, map, scale, &r2), HV_OK);
    cr_assert_gt(r2.mean_de2000, r.mean_de2000 + 1);
    /* the manifest hook */
    json_t *doc = json_pack("{s:[{s:s,s:f,s:f}]}", "materials", "name", "VeroYellow-V", "target", 0.2, "achieved", 0.4);
    hv_colour_skin sk = {.model = v, .map = map};
    cr_assert_eq(hv_colour_manifest_hook(&sk, doc), HV_OK, "%s", hv_last_error());
    json_t *c = json_object_get(doc, "colour");
    cr_assert_not_null(c);
    cr_assert_eq(json_integer_value(json_object_get(c, "skin_voxels")), (json_int_t)r.voxels);
    cr_assert(!sk.printer_voxels);
    cr_assert(fabs(json_number_value(json_object_get(c, "mean_de2000_target")) - r.mean_de2000) < 1e-9);
    cr_assert(fabs(json_number_value(json_object_get(c, "mean_de2000_achieved")) - r2.mean_de2000) < 1e-9);
    json_decref(doc);
    hv_colour_map_destroy(map);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}

Test(skin, an_unpainted_model_is_told)
{
    hv_mesh *m = t_cube_mesh(0, 2);
    hv_volume *v = t_voxelize(m, 0.5);
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_for_model(v, &map), HV_ERR_NOT_FOUND);
    cr_assert_null(map);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}

/* hv_colour_samples_error (a scan's colour table, issue 30): the painted cube's skin as weighted
 * samples (each distinct requested colour and fractions once, weighted by its voxels) gives the
 * model's figures, scaled fractions included; a sample of weight 0 counts for nothing; the
 * manifest hook takes samples in place of a model. */
Test(skin, weighted_samples_give_the_models_figures)
{
    hv_mesh *m = NULL;
    hv_volume *v = painted(&m, 0xC8C8B4FFu);
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_for_model(v, &map), HV_OK, "%s", hv_last_error());
    double scale[HV_COLOUR_SLOTS] = {1, 1, 1, 1, 1, 1};
    scale[HV_COLOUR_Y] = 2;
    hv_colour_skin_report r, rs;
    cr_assert_eq(hv_colour_skin_error(v, map, NULL, &r), HV_OK);
    cr_assert_eq(hv_colour_skin_error(v, map, scale, &rs), HV_OK);
    /* one colour everywhere: its fractions as the map gives them, weight = the skin voxels, and a
     * second far colour of weight 0 */
    uint8_t rgb[6] = {0xC8, 0xC8, 0xB4, 0, 0, 255};
    float fr[2 * HV_COLOUR_SLOTS];
    const uint8_t c0[4] = {0xC8, 0xC8, 0xB4, 0xFF}, c1[4] = {0, 0, 255, 0xFF};
    hv_colour_map_fractions(map, c0, fr);
    hv_colour_map_fractions(map, c1, fr + HV_COLOUR_SLOTS);
    uint64_t w[2] = {r.voxels, 0};
    hv_colour_skin_report s, ss;
    cr_assert_eq(hv_colour_samples_error(map, 2, rgb, fr, w, NULL, &s), HV_OK);
    cr_assert_eq(hv_colour_samples_error(map, 2, rgb, fr, w, scale, &ss), HV_OK);
    cr_assert_eq(s.voxels, r.voxels);
    cr_assert(fabs(s.mean_de2000 - r.mean_de2000) < 1e-3 && fabs(s.max_de2000 - r.max_de2000) < 1e-3,
              "samples %g (max %g), model %g (max %g)", s.mean_de2000, s.max_de2000, r.mean_de2000, r.max_de2000);
    cr_assert(fabs(ss.mean_de2000 - rs.mean_de2000) < 1e-3, "scaled: samples %g, model %g", ss.mean_de2000,
              rs.mean_de2000);
    /* weights make a weighted mean */
    w[1] = 3 * r.voxels;
    hv_colour_skin_report mix, blue;
    cr_assert_eq(hv_colour_samples_error(map, 2, rgb, fr, w, NULL, &mix), HV_OK);
    uint64_t wb[2] = {0, 1};
    cr_assert_eq(hv_colour_samples_error(map, 2, rgb, fr, wb, NULL, &blue), HV_OK);
    cr_assert(fabs(mix.mean_de2000 - (s.mean_de2000 + 3 * blue.mean_de2000) / 4) < 1e-9);
    cr_assert_eq(mix.max_de2000, fmax(s.max_de2000, blue.max_de2000));
    /* the hook with samples */
    json_t *doc = json_pack("{s:[{s:s,s:f,s:f}]}", "materials", "name", "VeroYellow-V", "target", 0.2, "achieved", 0.4);
    w[1] = 0;
    hv_colour_skin sk = {.map = map, .samples = 2, .rgb = rgb, .fractions = fr, .weight = w};
    cr_assert_eq(hv_colour_manifest_hook(&sk, doc), HV_OK, "%s", hv_last_error());
    json_t *c = json_object_get(doc, "colour");
    cr_assert_eq(json_integer_value(json_object_get(c, "printer_voxels")), (json_int_t)r.voxels);
    cr_assert(sk.printer_voxels, "the hook says its voxels are printer voxels");
    cr_assert(fabs(json_number_value(json_object_get(c, "mean_de2000_achieved")) - rs.mean_de2000) < 1e-3);
    json_decref(doc);
    hv_colour_map_destroy(map);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}
