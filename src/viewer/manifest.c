/* src/viewer/manifest.c - a slice stack's manifest.json (README "hovox layers", "hovox tray")
 * read into what a viewer page needs, every value checked: the manifest comes from a directory a
 * person points at, so it is input like any other file. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "viewer_internal.h"

#define VW_MAX_SIDE 1000000        /* pixels a side of a layer */
#define VW_MAX_LAYERS (1u << 24)
#define VW_MAX_PARTS 100000

int vw_path_ok(const char *p)
{
    size_t n = strlen(p);
    if (n == 0 || n > 1024 || p[0] == '/') return 0;
    for (size_t i = 0; i < n; ++i) {
        unsigned char c = (unsigned char)p[i];
        if (c < 0x20 || c == 0x7f || c == '\\') return 0;
    }
    for (const char *s = p; *s;) { /* every component non-empty, not . or .. */
        const char *e = strchr(s, '/');
        size_t len = e ? (size_t)(e - s) : strlen(s);
        if (len == 0 || (len == 1 && s[0] == '.') || (len == 2 && s[0] == '.' && s[1] == '.')) return 0;
        s += len + (e ? 1 : 0);
        if (e && !*s) return 0; /* a trailing slash */
    }
    return 1;
}

static int hexval(char c)
{
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

int vw_color_parse(const char *t, uint8_t rgb[3])
{
    if (!t || t[0] != '#' || strlen(t) != 7) return 0;
    for (int i = 0; i < 3; ++i) {
        int a = hexval(t[1 + 2 * i]), b = hexval(t[2 + 2 * i]);
        if (a < 0 || b < 0) return 0;
        rgb[i] = (uint8_t)(a * 16 + b);
    }
    return 1;
}

void vw_stack_free(vw_stack *s)
{
    if (!s) return;
    json_decref(s->doc);
    free(s->index);
    free(s->z);
    free((void *)s->files);
    free(s->names);
    free((void *)s->channel);
    free(s->channel_rgb);
    free(s->parts);
    memset(s, 0, sizeof *s);
}

static hv_status bad(const char *name, const char *fmt, const char *a, const char *b)
{
    return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s%s%s", name, fmt, a ? a : "", b ? b : "");
}

static hv_status get_int(const json_t *o, const char *key, const char *what, long long lo, long long hi, int *out)
{
    long long v;
    hv_status s = hv_json_get_int(o, key, what, lo, hi, &v);
    if (s == HV_OK) *out = (int)v;
    return s;
}

static hv_status get_path(const json_t *o, const char *key, const char *what, const char **out)
{
    hv_status s = hv_json_get_string(o, key, what, out);
    if (s == HV_OK && !vw_path_ok(*out))
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: %s \"%s\" is not a path inside the stack", what, key, *out);
    return s;
}

/* The common members: mode, sizes. */
static hv_status read_sizes(vw_stack *S, const char *name)
{
    const json_t *d = S->doc;
    const char *mode;
    hv_status s = hv_json_get_string(d, "mode", name, &mode);
    if (s != HV_OK) return s;
    /* the names hovox layers and tray write (hv_layers_mode_name), read by the same enum */
    if (hv_layers_mode_parse(mode, &S->mode) != HV_OK || (S->mode == HV_LAYERS_FRACTIONS && S->tray))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: mode \"%s\" is not %s", name, mode,
                             S->tray ? "halftone or mask" : "halftone, fractions or mask");
    if ((s = get_int(d, "width", name, 1, VW_MAX_SIDE, &S->width)) != HV_OK) return s;
    if ((s = get_int(d, "height", name, 1, VW_MAX_SIDE, &S->height)) != HV_OK) return s;
    if ((s = get_int(d, "bit_depth", name, 1, 8, &S->bit_depth)) != HV_OK) return s;
    int bd = S->bit_depth;
    if (bd != 1 && bd != 2 && bd != 4 && bd != 8)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: bit_depth %d is not 1, 2, 4 or 8", name, bd);
    if ((S->mode == HV_LAYERS_MASK && bd != 1) || (S->mode == HV_LAYERS_FRACTIONS && bd != 8))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: bit_depth %d does not suit mode %s (mask: 1, fractions: 8)", name,
                            bd, mode);
    if ((s = hv_json_get_number(d, "layer_height_mm", name, &S->layer_height)) != HV_OK) return s;
    if (!(S->layer_height > 0 && S->layer_height < 1e6))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: layer_height_mm %g is not a height in mm", name, S->layer_height);
    if ((s = hv_json_get_numbers(d, "dpi", name, S->dpi, 2)) != HV_OK) return s;
    for (int i = 0; i < 2; ++i)
        if (!(S->dpi[i] > 0 && S->dpi[i] <= 1e6))
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: dpi [%g, %g] are not resolutions in (0, 1e6]", name, S->dpi[0],
                                S->dpi[1]);
    return HV_OK;
}

/* ---- hovox layers ------------------------------------------------------------------------------- */

static hv_status read_layers_stack(vw_stack *S, const char *name)
{
    const json_t *d = S->doc;
    hv_status s = hv_json_get_numbers(d, "pixel_mm", name, S->pixel_mm, 2);
    if (s == HV_OK) s = hv_json_get_numbers(d, "origin_mm", name, S->origin_mm, 2);
    if (s != HV_OK) return s;
    if (!(S->pixel_mm[0] > 0 && S->pixel_mm[0] < 1e6 && fabs(S->pixel_mm[1]) > 0 && fabs(S->pixel_mm[1]) < 1e6) ||
        !(fabs(S->origin_mm[0]) < 1e9 && fabs(S->origin_mm[1]) < 1e9))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: pixel_mm [%g, %g] or origin_mm [%g, %g] out of range", name,
                            S->pixel_mm[0], S->pixel_mm[1], S->origin_mm[0], S->origin_mm[1]);
    const json_t *mats;
    if ((s = hv_json_need(d, "materials", JSON_ARRAY, name, &mats)) != HV_OK) return s;
    size_t m = json_array_size(mats);
    if (m > 255) return hv_error_set(HV_ERR_BAD_INPUT, "%s: %zu materials (at most 255)", name, m);
    char what[160];
    for (size_t j = 0; j < m; ++j) {
        const json_t *e = json_array_get(mats, j);
        snprintf(what, sizeof what, "%s: materials[%zu]", name, j);
        const char *nm, *col;
        uint8_t rgb[3];
        if ((s = hv_json_get_string(e, "name", what, &nm)) != HV_OK) return s;
        if ((s = hv_json_get_string(e, "color", what, &col)) != HV_OK) return s;
        if (!vw_color_parse(col, rgb)) return bad(what, "color \"", col, "\" is not #rrggbb");
        if (S->mode == HV_LAYERS_HALFTONE) {
            int pi;
            if ((s = get_int(e, "palette_index", what, 1, 255, &pi)) != HV_OK) return s;
        }
    }
    if (S->mode == HV_LAYERS_FRACTIONS) {
        if (m == 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: a fractions stack without materials", name);
        S->channels = (int)m;
        S->channel = hv_calloc(m, sizeof *S->channel);
        S->channel_rgb = hv_calloc(m, sizeof *S->channel_rgb);
        if (!S->channel || !S->channel_rgb) return HV_ERR_NOMEM;
        for (size_t j = 0; j < m; ++j) {
            const json_t *e = json_array_get(mats, j);
            S->channel[j] = json_string_value(json_object_get(e, "name"));
            vw_color_parse(json_string_value(json_object_get(e, "color")), S->channel_rgb[j]);
            for (size_t k = 0; k < j; ++k)
                if (strcmp(S->channel[k], S->channel[j]) == 0)
                    return bad(name, "material \"", S->channel[j], "\" is listed twice");
        }
    } else {
        S->channels = 1;
    }
    S->nchannel_names = S->mode == HV_LAYERS_FRACTIONS ? (int)m : 0;

    const json_t *layers;
    if ((s = hv_json_need(d, "layers", JSON_ARRAY, name, &layers)) != HV_OK) return s;
    size_t n = json_array_size(layers);
    if (n == 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: layers is empty: no layer to show", name);
    if (n > VW_MAX_LAYERS) return hv_error_set(HV_ERR_BAD_INPUT, "%s: %zu layers (at most %u)", name, n, VW_MAX_LAYERS);
    S->nlayers = n;
    S->index = hv_malloc_array(n, sizeof *S->index);
    S->z = hv_malloc_array(n, sizeof *S->z);
    S->files = hv_calloc(n * (size_t)S->channels, sizeof *S->files);
    if (!S->index || !S->z || !S->files) return HV_ERR_NOMEM;
    for (size_t i = 0; i < n; ++i) {
        const json_t *e = json_array_get(layers, i);
        snprintf(what, sizeof what, "%s: layers[%zu]", name, i);
        long long idx;
        if ((s = hv_json_get_int(e, "index", what, 0, (1LL << 40), &idx)) != HV_OK) return s;
        if (i > 0 && (size_t)idx <= S->index[i - 1])
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: index %lld does not follow %zu", what, idx, S->index[i - 1]);
        S->index[i] = (size_t)idx;
        if ((s = hv_json_get_number(e, "z_mm", what, &S->z[i])) != HV_OK) return s;
        if (!(fabs(S->z[i]) < 1e9)) return hv_error_set(HV_ERR_BAD_INPUT, "%s: z_mm %g out of range", what, S->z[i]);
        if (S->mode != HV_LAYERS_FRACTIONS) {
            if ((s = get_path(e, "file", what, &S->files[i])) != HV_OK) return s;
            continue;
        }
        const json_t *files;
        if ((s = hv_json_need(e, "files", JSON_OBJECT, what, &files)) != HV_OK) return s;
        char w2[200];
        snprintf(w2, sizeof w2, "%s: files", what);
        for (int j = 0; j < S->channels; ++j)
            if ((s = get_path(files, S->channel[j], w2, &S->files[i * (size_t)S->channels + (size_t)j])) != HV_OK)
                return s;
    }
    S->nparts = 1;
    S->parts = hv_calloc(1, sizeof *S->parts);
    if (!S->parts) return HV_ERR_NOMEM;
    const json_t *mesh = json_object_get(d, "mesh");
    S->mesh = json_is_string(mesh) ? json_string_value(mesh) : NULL;
    S->parts[0].name = S->mesh ? hv_basename(S->mesh) : "object";
    S->parts[0].box[2] = S->width;
    S->parts[0].box[3] = S->height;
    S->parts[0].l1 = n;
    return HV_OK;
}

/* ---- hovox tray ---------------------------------------------------------------------------------- */

static hv_status read_tray(vw_stack *S, const char *name)
{
    const json_t *d = S->doc;
    hv_status s;
    double plate[2];
    if ((s = hv_json_get_numbers(d, "plate_mm", name, plate, 2)) != HV_OK) return s;
    if (!(plate[0] > 0 && plate[0] < 1e6 && plate[1] > 0 && plate[1] < 1e6))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: plate_mm [%g, %g] out of range", name, plate[0], plate[1]);
    /* the plate frame (hovox/tray.h): pixel (c, r) covers x in [c sx, (c+1) sx), y down from the
     * far edge */
    S->pixel_mm[0] = 25.4 / S->dpi[0];
    S->pixel_mm[1] = -25.4 / S->dpi[1];
    S->origin_mm[0] = 0;
    S->origin_mm[1] = plate[1];
    long long first, last, total;
    if ((s = hv_json_get_int(d, "layers_total", name, 1, VW_MAX_LAYERS, &total)) != HV_OK) return s;
    if ((s = hv_json_get_int(d, "first", name, 0, total - 1, &first)) != HV_OK) return s;
    if ((s = hv_json_get_int(d, "last", name, first + 1, total, &last)) != HV_OK) return s;
    size_t n = (size_t)(last - first);
    S->nlayers = n;
    S->channels = 1;
    S->index = hv_malloc_array(n, sizeof *S->index);
    S->z = hv_malloc_array(n, sizeof *S->z);
    S->files = hv_calloc(n, sizeof *S->files);
    S->names = hv_malloc_array(n, 24);
    if (!S->index || !S->z || !S->files || !S->names) return HV_ERR_NOMEM;
    for (size_t i = 0; i < n; ++i) { /* tray layer t covers [t h, (t+1) h); cut at mid-height */
        S->index[i] = (size_t)first + i;
        S->z[i] = ((double)S->index[i] + 0.5) * S->layer_height;
        snprintf(S->names + 24 * i, 24, "layer-%05zu.png", S->index[i]);
        S->files[i] = S->names + 24 * i;
    }
    const json_t *pal, *parts;
    if ((s = hv_json_need(d, "palette", JSON_ARRAY, name, &pal)) != HV_OK) return s;
    size_t np = json_array_size(pal);
    if (np < 2 || np > (1u << S->bit_depth))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: a palette of %zu entries for %d-bit layers", name, np, S->bit_depth);
    char what[160];
    for (size_t i = 0; i < np; ++i) {
        const json_t *e = json_array_get(pal, i);
        snprintf(what, sizeof what, "%s: palette[%zu]", name, i);
        int idx;
        const char *col;
        uint8_t rgb[3];
        if ((s = get_int(e, "index", what, (long long)i, (long long)i, &idx)) != HV_OK) return s;
        if ((s = hv_json_get_string(e, "color", what, &col)) != HV_OK) return s;
        if (!vw_color_parse(col, rgb)) return bad(what, "color \"", col, "\" is not #rrggbb");
        const json_t *resin = json_object_get(e, "resin");
        if (resin && !json_is_string(resin) && !json_is_null(resin))
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: resin is not a string or null", what);
    }
    if ((s = hv_json_need(d, "parts", JSON_ARRAY, name, &parts)) != HV_OK) return s;
    size_t n_parts = json_array_size(parts);
    if (n_parts > VW_MAX_PARTS) return hv_error_set(HV_ERR_BAD_INPUT, "%s: %zu parts (at most %d)", name, n_parts, VW_MAX_PARTS);
    S->nparts = (int)n_parts;
    S->parts = hv_calloc(n_parts ? n_parts : 1, sizeof *S->parts);
    if (!S->parts) return HV_ERR_NOMEM;
    for (size_t i = 0; i < n_parts; ++i) {
        const json_t *e = json_array_get(parts, i);
        vw_part *p = &S->parts[i];
        snprintf(what, sizeof what, "%s: parts[%zu]", name, i);
        double px[4], box[4], ly[2];
        const json_t *mats;
        if ((s = hv_json_get_string(e, "name", what, &p->name)) != HV_OK) return s;
        if ((s = get_int(e, "copy", what, 1, 1 << 30, &p->copy)) != HV_OK) return s;
        if ((s = hv_json_get_numbers(e, "image_px", what, px, 4)) != HV_OK) return s;
        if ((s = hv_json_get_numbers(e, "box_mm", what, box, 4)) != HV_OK) return s;
        if ((s = hv_json_get_numbers(e, "layers", what, ly, 2)) != HV_OK) return s;
        if ((s = hv_json_need(e, "materials", JSON_OBJECT, what, &mats)) != HV_OK) return s;
        for (int k = 0; k < 4; ++k)
            if (px[k] != floor(px[k]) || px[k] < 0 || px[k] > VW_MAX_SIDE || !(fabs(box[k]) < 1e9))
                return hv_error_set(HV_ERR_BAD_INPUT, "%s: image_px or box_mm out of range", what);
        if (px[0] + px[2] > S->width || px[1] + px[3] > S->height || px[2] < 1 || px[3] < 1)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: image_px [%g, %g, %g, %g] is not inside the %d x %d plate", what,
                                px[0], px[1], px[2], px[3], S->width, S->height);
        if (ly[0] != floor(ly[0]) || ly[1] != floor(ly[1]) || ly[0] < 0 || ly[1] < ly[0] || ly[1] > (double)total)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: layers [%g, %g] is not a range of the tray's %lld layers", what,
                                ly[0], ly[1], total);
        for (int k = 0; k < 4; ++k) p->box[k] = (int)px[k];
        /* the part's layers among those written */
        double a = HV_MAX(ly[0], (double)first), b = HV_MIN(ly[1], (double)last);
        p->l0 = a < b ? (size_t)(a - (double)first) : 0;
        p->l1 = a < b ? (size_t)(b - (double)first) : 0;
        p->info = e;
    }
    return HV_OK;
}

hv_status vw_stack_parse(const char *text, size_t size, const char *name, vw_stack *out)
{
    memset(out, 0, sizeof *out);
    vw_stack S;
    memset(&S, 0, sizeof S);
    hv_status s = hv_json_parse(text, size, name, &S.doc);
    if (s != HV_OK) return s;
    const char *gen;
    if (!json_is_object(S.doc)) s = hv_error_set(HV_ERR_BAD_INPUT, "%s: not a JSON object", name);
    if (s == HV_OK) s = hv_json_get_string(S.doc, "generator", name, &gen);
    if (s == HV_OK && strncmp(gen, "hovox", 5) != 0)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: generator is \"%s\", not hovox", name, gen);
    const json_t *kind = json_object_get(S.doc, "kind");
    if (s == HV_OK && kind && !(json_is_string(kind) && strcmp(json_string_value(kind), "tray") == 0))
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: kind is not \"tray\"", name);
    S.tray = kind != NULL;
    if (s == HV_OK) s = read_sizes(&S, name);
    if (s == HV_OK) s = S.tray ? read_tray(&S, name) : read_layers_stack(&S, name);
    if (s != HV_OK) {
        vw_stack_free(&S);
        return s;
    }
    *out = S;
    return HV_OK;
}
