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

/* The skin's voxels: occupied, with a requested colour. */
static inline int skin_voxel(const uint64_t *on, const float *m, unsigned n)
{
    return ((on[n >> 6] >> (n & 63)) & 1u) && m[n] > 0.5f;
}

/* One pass over the skin for several scales at once (a tray's copies of a part share the
 * requested colours' Lab, made once): the leaves in batches of SKIN_DE values, each batch's dE2000
 * computed on the threads into de (scale s of voxel n of the batch's leaf b at
 * de[(b * 512 + n) * nscales + s]), then summed voxel by voxel in leaf order on the calling
 * thread, so the figures are those of one loop whatever the threads. */
enum { SKIN_DE = 1 << 20 }; /* dE2000 values a batch holds (8 MiB) */
typedef struct skin_pass {
    const hv_volume *model;
    const hv_colour_map *map;
    int rgb[3], mask, occ, grid[HV_COLOUR_SLOTS];
    int n;
    const double *const *scales;
    size_t l0; /* the batch's first leaf */
    double *de;
} skin_pass;

static hv_status skin_leaves(void *ctx, size_t b, size_t e, int thread)
{
    (void)thread;
    const skin_pass *P = ctx;
    for (size_t l = P->l0 + b; l < P->l0 + e; ++l) {
        const uint64_t *on = hv_volume_leaf_bool_c(P->model, P->occ, l);
        const float *m = hv_volume_leaf_float_c(P->model, P->mask, l), *c[3], *f[HV_COLOUR_SLOTS];
        for (int a = 0; a < 3; ++a) c[a] = hv_volume_leaf_float_c(P->model, P->rgb[a], l);
        for (int k = 0; k < HV_COLOUR_SLOTS; ++k)
            f[k] = P->grid[k] >= 0 ? hv_volume_leaf_float_c(P->model, P->grid[k], l) : NULL;
        double *de = P->de + (l - P->l0) * 512 * (size_t)P->n;
        for (unsigned n = 0; n < 512; ++n) {
            if (!skin_voxel(on, m, n)) continue;
            float fr[HV_COLOUR_SLOTS];
            for (int k = 0; k < HV_COLOUR_SLOTS; ++k) fr[k] = f[k] ? f[k][n] : 0.0f;
            uint8_t want[3];
            for (int a = 0; a < 3; ++a) want[a] = (uint8_t)lrintf(fminf(fmaxf(c[a][n], 0.0f), 1.0f) * 255.0f);
            double lw[3];
            hv_colour_map_lab_of_srgb(P->map, want, lw);
            for (int s = 0; s < P->n; ++s) {
                float g[HV_COLOUR_SLOTS];
                memcpy(g, fr, sizeof g);
                scale_fractions(g, P->scales[s]);
                double lg[3];
                hv_colour_map_lab_of_fractions(P->map, g, lg);
                de[(size_t)n * (size_t)P->n + (size_t)s] = hv_colour_delta_e2000(lw, lg);
            }
        }
    }
    return HV_OK;
}

hv_status hv_colour_skin_errors(const hv_volume *model, const hv_colour_map *map, int n, const double *const *scales,
                                hv_colour_skin_report *out)
{
    for (int s = 0; s < n; ++s) memset(&out[s], 0, sizeof out[s]);
    skin_pass P = {.model = model, .map = map, .n = n, .scales = scales};
    P.rgb[0] = hv_volume_grid_find(model, "colour.r");
    P.rgb[1] = hv_volume_grid_find(model, "colour.g");
    P.rgb[2] = hv_volume_grid_find(model, "colour.b");
    P.mask = hv_volume_grid_find(model, "colour.mask");
    P.occ = hv_volume_grid_find(model, "occupancy");
    if (P.rgb[0] < 0 || P.rgb[1] < 0 || P.rgb[2] < 0 || P.mask < 0 || P.occ < 0)
        return hv_error_set(HV_ERR_NOT_FOUND, "the model holds no requested colours (grids colour.r, .g, .b, .mask)");
    if (n < 1) return HV_OK;
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) P.grid[k] = slot_grid(model, map, k);
    size_t leaves = hv_volume_leaf_count(model);
    double *sum = hv_calloc((size_t)n, sizeof *sum);
    size_t batch = HV_MAX((size_t)SKIN_DE / (512 * (size_t)n), (size_t)1); /* leaves */
    P.de = hv_malloc_array(batch * 512 * (size_t)n, sizeof *P.de);
    hv_status st = sum && P.de ? HV_OK : hv_error_set(HV_ERR_NOMEM, "out of memory for the skin's dE2000");
    for (P.l0 = 0; P.l0 < leaves && st == HV_OK; P.l0 += batch) {
        size_t nb = HV_MIN(batch, leaves - P.l0);
        st = hv_parallel_for(nb, 16, skin_leaves, &P, NULL, "dE2000");
        for (size_t b = 0; b < nb && st == HV_OK; ++b) {
            const uint64_t *on = hv_volume_leaf_bool_c(model, P.occ, P.l0 + b);
            const float *m = hv_volume_leaf_float_c(model, P.mask, P.l0 + b);
            const double *de = P.de + b * 512 * (size_t)n;
            for (unsigned v = 0; v < 512; ++v) {
                if (!skin_voxel(on, m, v)) continue;
                for (int s = 0; s < n; ++s) {
                    double d = de[(size_t)v * (size_t)n + (size_t)s];
                    sum[s] += d;
                    out[s].max_de2000 = fmax(out[s].max_de2000, d);
                    out[s].voxels++;
                }
            }
        }
    }
    for (int s = 0; s < n && st == HV_OK; ++s) out[s].mean_de2000 = out[s].voxels ? sum[s] / (double)out[s].voxels : 0;
    free(sum);
    free(P.de);
    return st;
}

hv_status hv_colour_skin_error(const hv_volume *model, const hv_colour_map *map, const double scale[HV_COLOUR_SLOTS],
                               hv_colour_skin_report *out)
{
    const double *scales[1] = {scale};
    return hv_colour_skin_errors(model, map, 1, scales, out);
}

/* The target and, for each copy c with scale[c], the achieved figures of copies sk[0 .. copies)
 * (sk[0]'s model or samples, shared by all): one pass of the model for every distinct scale. */
static hv_status skin_figures(hv_colour_skin *sk, int copies, const double *const *scale)
{
    const double **sc = hv_calloc((size_t)copies + 1, sizeof *sc);
    int *slot = hv_calloc((size_t)copies + 1, sizeof *slot);
    hv_colour_skin_report *r = hv_calloc((size_t)copies + 1, sizeof *r);
    hv_status s = sc && slot && r ? HV_OK : hv_error_set(HV_ERR_NOMEM, "out of memory");
    int n = 1; /* sc[0] NULL: the target */
    for (int c = 0; c < copies && s == HV_OK && scale; ++c) {
        if (!scale[c]) continue;
        int k = 1; /* copies that print alike share their figures */
        while (k < n && memcmp(sc[k], scale[c], HV_COLOUR_SLOTS * sizeof *scale[c]) != 0) ++k;
        if (k == n) sc[n++] = scale[c];
        slot[c] = k;
    }
    if (s == HV_OK && sk->model) s = hv_colour_skin_errors(sk->model, sk->map, n, sc, r);
    for (int k = 0; k < n && s == HV_OK && !sk->model; ++k)
        s = hv_colour_samples_error(sk->map, sk->samples, sk->rgb, sk->fractions, sk->weight, sc[k], &r[k]);
    for (int c = 0; c < copies && s == HV_OK; ++c) {
        sk[c].target = r[0];
        sk[c].printer_voxels = !sk[0].model;
        sk[c].has_achieved = scale && scale[c];
        if (sk[c].has_achieved) sk[c].achieved = r[slot[c]];
    }
    free(sc);
    free(slot);
    free(r);
    return s;
}

/* The manifest's "colour" object of sk's figures (skin_figures). */
static hv_status skin_json(const hv_colour_skin *sk, json_t **out)
{
    *out = NULL;
    json_t *c = json_object();
    int bad = !c;
    bad |= hv_json_set(c, "icc", hv_json_text(hv_colour_map_icc(sk->map)));
    bad |= hv_json_set(c, "description", hv_json_text(hv_colour_map_description(sk->map)));
    bad |= hv_json_set(c, "intent", json_string(hv_intent_name(hv_colour_map_intent(sk->map))));
    bad |= hv_json_set(c, sk->printer_voxels ? "printer_voxels" : "skin_voxels", json_integer((json_int_t)sk->target.voxels));
    bad |= hv_json_set(c, "mean_de2000_target", hv_json_number(sk->target.mean_de2000));
    bad |= hv_json_set(c, "max_de2000_target", hv_json_number(sk->target.max_de2000));
    if (sk->has_achieved) bad |= hv_json_set(c, "mean_de2000_achieved", hv_json_number(sk->achieved.mean_de2000));
    char note[512];
    if (sk->model && hv_colour_paint_note(sk->model, note, sizeof note)) bad |= hv_json_set(c, "gives_way", hv_json_text(note));
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
    const double *sc[1] = {achieved ? scale : NULL};
    json_t *c = NULL;
    hv_status s = skin_figures(sk, 1, sc);
    if (s == HV_OK) s = skin_json(sk, &c);
    if (s == HV_OK && hv_json_set(doc, "colour", c)) s = hv_error_set(HV_ERR_NOMEM, "out of memory");
    return s;
}

hv_status hv_colour_skin_manifests(hv_colour_skin *sk, int copies, int m, const char *const *names,
                                   const double *const *target, const double *const *achieved, void **out)
{
    for (int c = 0; c < copies; ++c) out[c] = NULL;
    double(*scale)[HV_COLOUR_SLOTS] = hv_calloc((size_t)HV_MAX(copies, 1), sizeof *scale);
    const double **sc = hv_calloc((size_t)HV_MAX(copies, 1), sizeof *sc);
    hv_status s = scale && sc ? HV_OK : hv_error_set(HV_ERR_NOMEM, "out of memory");
    for (int c = 0; c < copies && s == HV_OK; ++c) {
        for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
            scale[c][k] = 1;
            for (int j = 0; j < m && achieved[c]; ++j)
                if (strcmp(names[j], hv_colour_map_resin(sk[0].map, k)) == 0 && target[c][j] > 0)
                    scale[c][k] = achieved[c][j] / target[c][j];
        }
        sc[c] = achieved[c] ? scale[c] : NULL;
    }
    if (s == HV_OK) s = skin_figures(sk, copies, sc);
    for (int c = 0; c < copies && s == HV_OK; ++c) s = skin_json(&sk[c], (json_t **)&out[c]);
    for (int c = 0; c < copies && s != HV_OK; ++c) {
        json_decref(out[c]);
        out[c] = NULL;
    }
    free(scale);
    free(sc);
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
