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
#include "hovox/voxelize.h"
#include "support/support.h"

/* A 6 mm cube painted 1 mm deep over an Agilus30 core: every facet in rgba, or (rgba 0) each in a
 * colour of its own. */
static hv_volume *painted(hv_mesh **mesh, uint32_t rgba)
{
    hv_mesh *m = t_cube_mesh(0, 6);
    size_t nf = hv_mesh_facet_count(m);
    uint32_t *c = malloc(3 * nf * sizeof *c);
    for (size_t i = 0; i < 3 * nf; ++i)
        c[i] = rgba ? rgba : (uint32_t)(0x30 + 40 * (i / 3 % 5)) << 24 | (uint32_t)(0xE0 - 30 * (i / 3 % 7)) << 16 |
                                 (uint32_t)(0x50 + 17 * (i / 3)) << 8 | 0xFFu;
    cr_assert_eq(hv_mesh_set_corner_colours(m, c), HV_OK);
    free(c);
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.5;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_OK, "%s", hv_last_error());
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_create(NULL, &map), HV_OK);
    cr_assert_eq(hv_colour_paint(v, m, map, 1.0, "Agilus30", NULL), HV_OK, "%s", hv_last_error());
    hv_colour_map_destroy(map);
    *mesh = m;
    return v;
}

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
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.5;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_OK);
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

/* What a halftone's scale does to the fractions, as the skin's figures take it (skin.c). */
static double expected_de(const hv_colour_map *map, const uint8_t want[3], const float fr[HV_COLOUR_SLOTS],
                          const double *scale)
{
    float f[HV_COLOUR_SLOTS];
    double total = 0;
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
        double v = (double)fr[k] * (scale ? scale[k] : 1.0);
        f[k] = (float)v;
        total += v;
    }
    for (int k = 0; k < HV_COLOUR_SLOTS && total > 0; ++k) f[k] = (float)(f[k] / total);
    double lw[3], lg[3];
    hv_colour_map_lab_of_srgb(map, want, lw);
    hv_colour_map_lab_of_fractions(map, f, lg);
    return hv_colour_delta_e2000(lw, lg);
}

/* hv_colour_skin_errors: many scales in one pass (700: the pass then holds two leaves at a time)
 * give, to the last bit and on one thread or two, each scale's figures of a voxel-by-voxel loop in
 * leaf order; hv_colour_skin_manifests gives copies that printed alike the same figures and each
 * copy those of the manifest hook alone. */
Test(skin, several_scales_in_one_pass_are_each_ones_figures)
{
    hv_mesh *m = NULL;
    hv_volume *v = painted(&m, 0);
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_for_model(v, &map), HV_OK, "%s", hv_last_error());
    enum { N = 700 };
    static double sc[N][HV_COLOUR_SLOTS];
    const double *scales[N];
    for (int s = 0; s < N; ++s) {
        for (int k = 0; k < HV_COLOUR_SLOTS; ++k) sc[s][k] = 1 + 0.002 * (double)((s * (k + 3)) % 97);
        scales[s] = s % 5 == 0 ? NULL : sc[s];
    }
    int occ = hv_volume_grid_find(v, "occupancy"), mask = hv_volume_grid_find(v, "colour.mask");
    int rgb[3] = {hv_volume_grid_find(v, "colour.r"), hv_volume_grid_find(v, "colour.g"), hv_volume_grid_find(v, "colour.b")};
    int grid[HV_COLOUR_SLOTS];
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
        char name[160];
        snprintf(name, sizeof name, "material.%s", hv_colour_map_resin(map, k));
        grid[k] = hv_volume_grid_find(v, name);
    }
    cr_assert_gt(hv_volume_leaf_count(v), 4);
    static double sum[N], max[N];
    uint64_t voxels = 0;
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        const uint64_t *on = hv_volume_leaf_bool_c(v, occ, l);
        const float *mk = hv_volume_leaf_float_c(v, mask, l);
        for (unsigned n = 0; n < 512; ++n) {
            if (!((on[n >> 6] >> (n & 63)) & 1u) || !(mk[n] > 0.5f)) continue;
            uint8_t want[3];
            for (int a = 0; a < 3; ++a)
                want[a] = (uint8_t)lrintf(fminf(fmaxf(hv_volume_leaf_float_c(v, rgb[a], l)[n], 0.0f), 1.0f) * 255.0f);
            float fr[HV_COLOUR_SLOTS];
            for (int k = 0; k < HV_COLOUR_SLOTS; ++k) fr[k] = grid[k] >= 0 ? hv_volume_leaf_float_c(v, grid[k], l)[n] : 0;
            for (int s = 0; s < N; ++s) {
                double de = expected_de(map, want, fr, scales[s]);
                sum[s] += de;
                max[s] = fmax(max[s], de);
            }
            voxels++;
        }
    }
    static hv_colour_skin_report r[N], r1[N];
    hv_set_threads(2);
    cr_assert_eq(hv_colour_skin_errors(v, map, N, scales, r), HV_OK, "%s", hv_last_error());
    hv_set_threads(1);
    cr_assert_eq(hv_colour_skin_errors(v, map, N, scales, r1), HV_OK, "%s", hv_last_error());
    hv_set_threads(0);
    double lo = 1e9, hi = 0;
    for (int s = 0; s < N; ++s) {
        cr_assert_eq(r[s].voxels, voxels);
        cr_assert(r[s].mean_de2000 == sum[s] / (double)voxels && r[s].max_de2000 == max[s],
                  "scale %d: mean %.17g max %.17g, voxel by voxel %.17g %.17g", s, r[s].mean_de2000, r[s].max_de2000,
                  sum[s] / (double)voxels, max[s]);
        cr_assert(memcmp(&r[s], &r1[s], sizeof r[s]) == 0, "scale %d: one thread and two differ", s);
        lo = fmin(lo, r[s].mean_de2000);
        hi = fmax(hi, r[s].mean_de2000);
    }
    cr_assert_gt(hi - lo, 0.01, "the scales move the figures (%g .. %g)", lo, hi);
    /* three copies, the first and the last printed alike */
    const char *names[2] = {"VeroYellow-V", "VeroCyan-V"};
    double tg[3][2] = {{0.2, 0.1}, {0.2, 0.1}, {0.2, 0.1}}, ac[3][2] = {{0.3, 0.1}, {0.2, 0.15}, {0.3, 0.1}};
    const double *tgp[3] = {tg[0], tg[1], tg[2]}, *acp[3] = {ac[0], ac[1], ac[2]};
    hv_colour_skin sk[3] = {{.model = v, .map = map}};
    sk[1] = sk[2] = sk[0];
    void *out[3];
    cr_assert_eq(hv_colour_skin_manifests(sk, 3, 2, names, tgp, acp, out), HV_OK, "%s", hv_last_error());
    for (int c = 0; c < 3; ++c) {
        json_t *doc = json_pack("{s:[{s:s,s:f,s:f},{s:s,s:f,s:f}]}", "materials", "name", names[0], "target", tg[c][0],
                                "achieved", ac[c][0], "name", names[1], "target", tg[c][1], "achieved", ac[c][1]);
        hv_colour_skin one = {.model = v, .map = map};
        cr_assert_eq(hv_colour_manifest_hook(&one, doc), HV_OK, "%s", hv_last_error());
        cr_assert(json_equal(out[c], json_object_get(doc, "colour")), "copy %d", c);
        cr_assert(sk[c].has_achieved && memcmp(&sk[c].achieved, &one.achieved, sizeof one.achieved) == 0);
        cr_assert(memcmp(&sk[c].target, &one.target, sizeof one.target) == 0);
        json_decref(doc);
    }
    cr_assert(sk[0].achieved.mean_de2000 == sk[2].achieved.mean_de2000);
    cr_assert(sk[0].achieved.mean_de2000 != sk[1].achieved.mean_de2000);
    for (int c = 0; c < 3; ++c) json_decref(out[c]);
    hv_colour_map_destroy(map);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}
