/* src/colour/skin.c - what a painted model asked for (hovox/colour.h): the profile hv_colour_paint
 * used (metadata hovox.colour.json), the colour map made again from it, and the mean CIEDE2000
 * (Sharma, Wu, Dalal 2005) between each skin voxel's requested colour (grids colour.r, .g, .b
 * where colour.mask is set) and what its six fractions print, for the stack manifest. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "core/json.h"
#include "hovox/colour.h"
#include "hovox/volume.h"

#define META "hovox.colour.json"

hv_status hv_colour_map_for_model(const hv_volume *model, hv_colour_map **out)
{
    *out = NULL;
    const char *text = hv_volume_meta_string(model, META);
    if (!text) return hv_error_set(HV_ERR_NOT_FOUND, "the model is not painted in colour (no %s)", META);
    json_t *doc = NULL;
    hv_status s = hv_json_parse(text, strlen(text), META, &doc);
    const char *icc = NULL, *intent = NULL;
    if (s == HV_OK) s = hv_json_get_string(doc, "icc", META, &icc);
    if (s == HV_OK) s = hv_json_get_string(doc, "intent", META, &intent);
    const json_t *resins = NULL;
    if (s == HV_OK) s = hv_json_need(doc, "resins", JSON_ARRAY, META, &resins);
    if (s == HV_OK && json_array_size(resins) != HV_COLOUR_SLOTS)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: resins must name six resins", META);
    hv_buf names;
    hv_buf_init(&names);
    for (size_t k = 0; k < HV_COLOUR_SLOTS && s == HV_OK; ++k) {
        const char *r = json_string_value(json_array_get(resins, k));
        if (!r || strchr(r, ',')) s = hv_error_set(HV_ERR_BAD_INPUT, "%s: resins[%zu] is not a resin name", META, k);
        else hv_buf_printf(&names, "%s%s", k ? "," : "", r);
    }
    hv_colour_options opt;
    hv_colour_options_init(&opt);
    if (s == HV_OK && hv_intent_parse(intent, &opt.intent) != 0)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: unknown intent '%s'", META, intent);
    if (s == HV_OK && names.failed) s = HV_ERR_NOMEM;
    if (s == HV_OK) {
        opt.icc = icc;
        opt.resins = names.data;
        s = hv_colour_map_create(&opt, out);
    }
    hv_buf_free(&names);
    json_decref(doc);
    return s;
}

/* The grid of slot k's resin, or -1 when the model has none. */
static int slot_grid(const hv_volume *model, const hv_colour_map *map, int k)
{
    char name[160];
    snprintf(name, sizeof name, "material.%s", hv_colour_map_resin(map, k));
    return hv_volume_grid_find(model, name);
}

/* Fractions scaled per resin (a halftone's achieved over target share; NULL: as they are),
 * normalised. */
static void scale_fractions(float fr[HV_COLOUR_SLOTS], const double *scale)
{
    double total = 0;
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
        double v = (double)fr[k] * (scale ? scale[k] : 1.0);
        fr[k] = (float)v;
        total += v;
    }
    for (int k = 0; k < HV_COLOUR_SLOTS && total > 0; ++k) fr[k] = (float)(fr[k] / total);
}

/* CIEDE2000 between a requested colour and what fractions print (both through the map). */
static double sample_de(const hv_colour_map *map, const uint8_t want[3], const float fr[HV_COLOUR_SLOTS], const double *scale)
{
    float f[HV_COLOUR_SLOTS];
    memcpy(f, fr, sizeof f);
    scale_fractions(f, scale);
    double lw[3], lg[3];
    hv_colour_map_lab_of_srgb(map, want, lw);
    hv_colour_map_lab_of_fractions(map, f, lg);
    return hv_colour_delta_e2000(lw, lg);
}

hv_status hv_colour_samples_error(const hv_colour_map *map, size_t n, const uint8_t *rgb, const float *fractions,
                                  const uint64_t *weight, const double scale[HV_COLOUR_SLOTS], hv_colour_skin_report *out)
{
    memset(out, 0, sizeof *out);
    double sum = 0;
    for (size_t i = 0; i < n; ++i) {
        if (!weight[i]) continue;
        double de = sample_de(map, rgb + 3 * i, fractions + HV_COLOUR_SLOTS * i, scale);
        sum += de * (double)weight[i];
        out->max_de2000 = fmax(out->max_de2000, de);
        out->voxels += weight[i];
    }
    out->mean_de2000 = out->voxels ? sum / (double)out->voxels : 0;
    return HV_OK;
}

hv_status hv_colour_skin_error(const hv_volume *model, const hv_colour_map *map, const double scale[HV_COLOUR_SLOTS],
                               hv_colour_skin_report *out)
{
    memset(out, 0, sizeof *out);
    int rgb[3] = {hv_volume_grid_find(model, "colour.r"), hv_volume_grid_find(model, "colour.g"),
                  hv_volume_grid_find(model, "colour.b")};
    int mask = hv_volume_grid_find(model, "colour.mask"), occ = hv_volume_grid_find(model, "occupancy");
    if (rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0 || mask < 0 || occ < 0)
        return hv_error_set(HV_ERR_NOT_FOUND, "the model holds no requested colours (grids colour.r, .g, .b, .mask)");
    int grid[HV_COLOUR_SLOTS];
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) grid[k] = slot_grid(model, map, k);
    double sum = 0;
    for (size_t l = 0; l < hv_volume_leaf_count(model); ++l) {
        const uint64_t *on = hv_volume_leaf_bool_c(model, occ, l);
        const float *m = hv_volume_leaf_float_c(model, mask, l), *c[3], *f[HV_COLOUR_SLOTS];
        for (int a = 0; a < 3; ++a) c[a] = hv_volume_leaf_float_c(model, rgb[a], l);
        for (int k = 0; k < HV_COLOUR_SLOTS; ++k) f[k] = grid[k] >= 0 ? hv_volume_leaf_float_c(model, grid[k], l) : NULL;
        for (unsigned n = 0; n < 512; ++n) {
            if (!((on[n >> 6] >> (n & 63)) & 1u) || !(m[n] > 0.5f)) continue;
            float fr[HV_COLOUR_SLOTS];
            for (int k = 0; k < HV_COLOUR_SLOTS; ++k) fr[k] = f[k] ? f[k][n] : 0.0f;
            uint8_t want[3];
            for (int a = 0; a < 3; ++a) want[a] = (uint8_t)lrintf(fminf(fmaxf(c[a][n], 0.0f), 1.0f) * 255.0f);
            double de = sample_de(map, want, fr, scale);
            sum += de;
            out->max_de2000 = fmax(out->max_de2000, de);
            out->voxels++;
        }
    }
    out->mean_de2000 = out->voxels ? sum / (double)out->voxels : 0;
    return HV_OK;
}

/* The manifest's "colour" object of sk (target and, with scale, achieved filled in). */
static hv_status skin_json(hv_colour_skin *sk, const double *scale, json_t **out)
{
    *out = NULL;
    hv_status s = sk->model ? hv_colour_skin_error(sk->model, sk->map, NULL, &sk->target)
                            : hv_colour_samples_error(sk->map, sk->samples, sk->rgb, sk->fractions, sk->weight, NULL,
                                                      &sk->target);
    if (s == HV_OK && scale)
        s = sk->model ? hv_colour_skin_error(sk->model, sk->map, scale, &sk->achieved)
                      : hv_colour_samples_error(sk->map, sk->samples, sk->rgb, sk->fractions, sk->weight, scale,
                                                &sk->achieved);
    if (s != HV_OK) return s;
    sk->has_achieved = scale != NULL;
    sk->printer_voxels = !sk->model;
    json_t *c = json_object();
    int bad = !c;
    bad |= hv_json_set(c, "icc", hv_json_text(hv_colour_map_icc(sk->map)));
    bad |= hv_json_set(c, "description", hv_json_text(hv_colour_map_description(sk->map)));
    bad |= hv_json_set(c, "intent", json_string(hv_intent_name(hv_colour_map_intent(sk->map))));
    bad |= hv_json_set(c, sk->printer_voxels ? "printer_voxels" : "skin_voxels", json_integer((json_int_t)sk->target.voxels));
    bad |= hv_json_set(c, "mean_de2000_target", hv_json_number(sk->target.mean_de2000));
    bad |= hv_json_set(c, "max_de2000_target", hv_json_number(sk->target.max_de2000));
    if (scale) bad |= hv_json_set(c, "mean_de2000_achieved", hv_json_number(sk->achieved.mean_de2000));
    if (bad) {
        json_decref(c);
        return hv_error_set(HV_ERR_NOMEM, "out of memory");
    }
    *out = c;
    return HV_OK;
}

hv_status hv_colour_manifest_hook(void *user, void *manifest)
{
    hv_colour_skin *sk = user;
    json_t *doc = manifest, *mats = json_object_get(doc, "materials");
    double scale[HV_COLOUR_SLOTS];
    int achieved = 1;
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
        scale[k] = 1;
        size_t i;
        json_t *e;
        json_array_foreach(mats, i, e) {
            const char *name = json_string_value(json_object_get(e, "name"));
            if (!name || strcmp(name, hv_colour_map_resin(sk->map, k)) != 0) continue;
            double t = json_number_value(json_object_get(e, "target"));
            json_t *a = json_object_get(e, "achieved");
            if (!a) achieved = 0;
            scale[k] = a && t > 0 ? json_number_value(a) / t : 1;
        }
    }
    json_t *c;
    hv_status s = skin_json(sk, achieved ? scale : NULL, &c);
    char note[512];
    if (s == HV_OK && sk->model && hv_colour_paint_note(sk->model, note, sizeof note) && hv_json_set(c, "gives_way", hv_json_text(note)))
        s = hv_error_set(HV_ERR_NOMEM, "out of memory");
    if (s == HV_OK && hv_json_set(doc, "colour", c)) s = hv_error_set(HV_ERR_NOMEM, "out of memory");
    return s;
}

hv_status hv_colour_skin_manifest(hv_colour_skin *sk, int m, const char *const *names, const double *target,
                                  const double *achieved, void **out)
{
    *out = NULL;
    double scale[HV_COLOUR_SLOTS];
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
        scale[k] = 1;
        for (int j = 0; j < m && achieved; ++j)
            if (strcmp(names[j], hv_colour_map_resin(sk->map, k)) == 0 && target[j] > 0) scale[k] = achieved[j] / target[j];
    }
    json_t *c = NULL;
    hv_status s = skin_json(sk, achieved ? scale : NULL, &c);
    char note[512];
    if (s == HV_OK && sk->model && hv_colour_paint_note(sk->model, note, sizeof note) &&
        hv_json_set(c, "gives_way", hv_json_text(note)))
        s = hv_error_set(HV_ERR_NOMEM, "out of memory");
    *out = c;
    return s;
}

hv_status hv_colour_part_manifest(const hv_volume *model, int m, const char *const *names, const double *target,
                                  const double *achieved, void **out)
{
    *out = NULL;
    if (!hv_volume_meta_string(model, META)) return HV_OK;
    hv_colour_skin sk;
    memset(&sk, 0, sizeof sk);
    sk.model = model;
    hv_status s = hv_colour_map_for_model(model, &sk.map);
    if (s == HV_OK) s = hv_colour_skin_manifest(&sk, m, names, target, achieved, out);
    hv_colour_map_destroy(sk.map);
    return s;
}

int hv_colour_paint_note(const hv_volume *model, char *buf, size_t size)
{
    if (size) buf[0] = '\0';
    const char *text = hv_volume_meta_string(model, META);
    json_t *doc = text ? json_loads(text, 0, NULL) : NULL;
    json_t *g = json_object_get(doc, "gives_way");
    const char *resin = json_string_value(json_object_get(g, "resin")), *into = json_string_value(json_object_get(g, "into"));
    const char *core = json_string_value(json_object_get(doc, "core"));
    int gave = resin && into && core;
    if (gave) {
        double share = json_number_value(json_object_get(g, "share"));
        char used[64];
        if (share > 0) snprintf(used, sizeof used, "%.2g%% of the colour's fractions", 100 * share);
        snprintf(buf, size, "%s gave way to the core %s (six slots): %s; folded into %s", resin, core,
                 share > 0 ? used : "no painted voxel used it", into);
    }
    json_decref(doc);
    return gave;
}
