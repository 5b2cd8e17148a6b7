/* src/material/table.c - the material space V^m (Wu 2.2, after Kumar): named primitives
 * with display colours and physical properties, their JSON form in volume metadata, and the
 * composition check of Wu eq. 12 (fractions >= 0 summing to 1; errors, never clamps). */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/internal.h"
#include "hovox/material.h"
#include "material_internal.h"
#include "volumes/schema.h"

typedef struct property {
    char *key, *unit;
    double value;
} property;

typedef struct material {
    char *name;
    float rgba[4];
    int nprops;
    size_t pcap;
    property *props;
} material;

struct hv_material_table {
    int n;
    material mats[HV_MAX_MATERIALS];
};

/* tab10 without grey: distinguishable for the common 2-6 materials */
static const float PALETTE[][3] = {
    {0.122f, 0.467f, 0.706f}, {1.000f, 0.498f, 0.055f}, {0.173f, 0.627f, 0.173f},
    {0.839f, 0.153f, 0.157f}, {0.580f, 0.404f, 0.741f}, {0.549f, 0.337f, 0.294f},
    {0.890f, 0.467f, 0.761f}, {0.737f, 0.741f, 0.133f}, {0.090f, 0.745f, 0.812f}};

void hv_material_palette(int i, float rgba[4])
{
    int n = (int)HV_COUNT(PALETTE);
    const float *c = PALETTE[((i % n) + n) % n];
    rgba[0] = c[0];
    rgba[1] = c[1];
    rgba[2] = c[2];
    rgba[3] = 1.0f;
}

/* Public colour names of PolyJet resins for the J750/J850 (Stratasys material data sheets);
 * the display colours are ours. Not vendor-confirmed: a tray job may override them. */
static const hv_resin k_resins[] = {
    {"VeroCyan-V", {0x00, 0x9f, 0xe3}},      {"VeroMagenta-V", {0xd4, 0x0f, 0x7d}},
    {"VeroYellow-V", {0xf5, 0xd5, 0x00}},    {"VeroBlackPlus", {0x20, 0x20, 0x20}},
    {"VeroPureWhite", {0xf4, 0xf4, 0xf0}},   {"VeroClear", {0xb8, 0xd8, 0xe0}},
    {"VeroUltraClear", {0xe0, 0xee, 0xf2}},  {"Agilus30Clear", {0xd8, 0xd4, 0xb8}},
    {"Agilus30Black", {0x38, 0x38, 0x38}},   {"Agilus30White", {0xe8, 0xe8, 0xe0}},
};

const hv_resin *hv_resin_table(int *n)
{
    *n = (int)HV_COUNT(k_resins);
    return k_resins;
}

const hv_resin *hv_resin_find(const char *name)
{
    for (size_t i = 0; name && i < HV_COUNT(k_resins); ++i)
        if (strcasecmp(k_resins[i].name, name) == 0) return &k_resins[i];
    return NULL;
}

hv_status hv_material_table_create(hv_material_table **out)
{
    *out = hv_calloc(1, sizeof **out);
    return *out ? HV_OK : HV_ERR_NOMEM;
}

void hv_material_table_destroy(hv_material_table *t)
{
    if (!t) return;
    for (int i = 0; i < t->n; ++i) {
        free(t->mats[i].name);
        for (int p = 0; p < t->mats[i].nprops; ++p) {
            free(t->mats[i].props[p].key);
            free(t->mats[i].props[p].unit);
        }
        free(t->mats[i].props);
    }
    free(t);
}

static int valid_name(const char *s, const char *extra)
{
    size_t n = s ? strlen(s) : 0;
    if (n == 0 || n > 64) return 0;
    for (size_t i = 0; i < n; ++i)
        if (!isalnum((unsigned char)s[i]) && !strchr(extra, s[i])) return 0;
    return 1;
}

hv_status hv_material_add(hv_material_table *t, const char *name, const float rgba[4], int *index)
{
    if (!valid_name(name, "_-"))
        return hv_error_set(HV_ERR_INVALID,
                            "material name '%s' must have 1-64 characters of A-Z a-z 0-9 _ -",
                            name ? name : "");
    if (hv_material_find(t, name) >= 0)
        return hv_error_set(HV_ERR_INVALID, "material '%s' is defined twice", name);
    if (t->n >= HV_MAX_MATERIALS)
        return hv_error_set(HV_ERR_INVALID, "at most %d materials", HV_MAX_MATERIALS);
    float c[4];
    if (rgba) {
        for (int k = 0; k < 4; ++k)
            if (!(rgba[k] >= 0 && rgba[k] <= 1))
                return hv_error_set(HV_ERR_INVALID, "material '%s': colour component %d is %g, not in [0,1]",
                                    name, k, (double)rgba[k]);
        memcpy(c, rgba, sizeof c);
    } else if (hv_resin_find(name)) { /* one colour per resin: layers, render and trays agree */
        const hv_resin *r = hv_resin_find(name);
        for (int k = 0; k < 3; ++k) c[k] = (float)r->rgb[k] / 255.0f;
        c[3] = 1.0f;
    } else {
        hv_material_palette(t->n, c);
    }
    material *m = &t->mats[t->n];
    memset(m, 0, sizeof *m);
    m->name = hv_strdup(name);
    if (!m->name) return HV_ERR_NOMEM;
    memcpy(m->rgba, c, sizeof c);
    if (index) *index = t->n;
    ++t->n;
    return HV_OK;
}

/* "A,B,C" -> names; -1 on an empty or over-long name or more than max */
static int split_names(const char *s, char names[][65], int max)
{
    int n = 0;
    for (const char *p = s; n < max;) {
        const char *c = strchr(p, ',');
        size_t len = c ? (size_t)(c - p) : strlen(p);
        if (len == 0 || len > 64) return -1;
        memcpy(names[n], p, len);
        names[n++][len] = '\0';
        if (!c) return n;
        p = c + 1;
    }
    return -1;
}

/* "MATERIAL:KEY=VALUE[:UNIT]" */
static hv_status parse_property(hv_material_table *t, const char *spec)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s", spec);
    char *colon = strchr(buf, ':'), *eq = colon ? strchr(colon, '=') : NULL, *unit = NULL;
    if (!colon || !eq) return hv_error_option(HV_ERR_INVALID, "{property} '%s': expected MATERIAL:KEY=VALUE[:UNIT]", spec);
    *colon = *eq = '\0';
    if ((unit = strchr(eq + 1, ':'))) *unit++ = '\0';
    int mi = hv_material_find(t, buf);
    double v;
    static const hv_option num = {.key = "property", .kind = HV_OPT_NUMBER};
    if (mi < 0) return hv_error_option(HV_ERR_INVALID, "{property} '%s': no material '%s'", spec, buf);
    if (hv_option_set_text(&num, &v, eq + 1) != HV_OK) return HV_ERR_INVALID;
    return hv_material_set_property(t, mi, colon + 1, v, unit ? unit : hv_property_si_unit(colon + 1));
}

hv_status hv_material_table_amend(hv_material_table *t, const char *colors, const char *const *props, int nprops)
{
    char cols[HV_MAX_MATERIALS][65];
    int m = t->n;
    int nc = colors ? split_names(colors, cols, HV_MAX_MATERIALS) : m;
    hv_status s = HV_OK;
    if (nc != m) s = hv_error_option(HV_ERR_INVALID, "{colors}: %d colours for %d materials", nc < 0 ? 0 : nc, m);
    for (int j = 0; colors && j < m && s == HV_OK; ++j) {
        float rgba[4];
        if ((s = hv_color_parse(cols[j], rgba)) == HV_OK) s = hv_material_set_color(t, j, rgba);
    }
    for (int i = 0; i < nprops && s == HV_OK; ++i) s = parse_property(t, props[i]);
    return s;
}

hv_status hv_material_table_parse(const char *names, const char *colors, const char *const *props, int nprops,
                                  hv_material_table **out)
{
    char nm[HV_MAX_MATERIALS][65];
    *out = NULL;
    int m = names ? split_names(names, nm, HV_MAX_MATERIALS) : -1;
    if (m < 1) return hv_error_option(HV_ERR_INVALID, "{materials} '%s': expected comma-separated names", names ? names : "");
    hv_material_table *t;
    hv_status s = hv_material_table_create(&t);
    if (s != HV_OK) return s;
    for (int j = 0; j < m && s == HV_OK; ++j) s = hv_material_add(t, nm[j], NULL, NULL);
    if (s == HV_OK) s = hv_material_table_amend(t, colors, props, nprops);
    if (s == HV_OK) *out = t;
    else hv_material_table_destroy(t);
    return s;
}

void hv_material_name_from(const char *text, char out[65])
{
    size_t k = 0;
    for (const char *p = text ? text : ""; *p && k < 64; ++p) {
        unsigned char c = (unsigned char)*p;
        out[k++] = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-'
                       ? (char)c
                       : '_';
    }
    out[k] = '\0';
    if (k == 0) snprintf(out, 65, "material");
}

int hv_material_count(const hv_material_table *t) { return t->n; }

const char *hv_material_name(const hv_material_table *t, int m)
{
    return m >= 0 && m < t->n ? t->mats[m].name : NULL;
}

int hv_material_find(const hv_material_table *t, const char *name)
{
    for (int i = 0; i < t->n; ++i)
        if (strcmp(t->mats[i].name, name) == 0) return i;
    return -1;
}

void hv_material_color(const hv_material_table *t, int m, float rgba[4])
{
    memcpy(rgba, t->mats[m].rgba, 4 * sizeof(float));
}

hv_status hv_material_set_color(hv_material_table *t, int m, const float rgba[4])
{
    if (m < 0 || m >= t->n) return hv_error_set(HV_ERR_INVALID, "no material %d", m);
    for (int k = 0; k < 4; ++k)
        if (!(rgba[k] >= 0 && rgba[k] <= 1))
            return hv_error_set(HV_ERR_INVALID, "colour component %d is %g, not in [0,1]", k, (double)rgba[k]);
    memcpy(t->mats[m].rgba, rgba, 4 * sizeof(float));
    return HV_OK;
}

const char *hv_property_si_unit(const char *key)
{
    static const struct { const char *key, *si; } keys[] = {
        {"density", "kg/m^3"},      {"youngs_modulus", "Pa"}, {"shear_modulus", "Pa"},
        {"bulk_modulus", "Pa"},     {"poisson_ratio", "1"}};
    for (size_t i = 0; key && i < HV_COUNT(keys); ++i)
        if (strcmp(key, keys[i].key) == 0) return keys[i].si;
    return "";
}

hv_status hv_material_set_property(hv_material_table *t, int m, const char *key, double value,
                                   const char *unit)
{
    if (m < 0 || m >= t->n) return hv_error_set(HV_ERR_INVALID, "no material %d", m);
    if (!valid_name(key, "_.-"))
        return hv_error_set(HV_ERR_INVALID, "property key '%s' must have 1-64 characters of A-Z a-z 0-9 _ . -",
                            key ? key : "");
    if (!isfinite(value))
        return hv_error_set(HV_ERR_INVALID, "material '%s': property %s = %g is not finite",
                            t->mats[m].name, key, value);
    material *mt = &t->mats[m];
    char *u = hv_strdup(unit ? unit : "");
    if (!u) return HV_ERR_NOMEM;
    for (int i = 0; i < mt->nprops; ++i)
        if (strcmp(mt->props[i].key, key) == 0) {
            free(mt->props[i].unit);
            mt->props[i].unit = u;
            mt->props[i].value = value;
            return HV_OK;
        }
    char *k = hv_strdup(key);
    if (!k || hv_grow((void **)&mt->props, &mt->pcap, (size_t)mt->nprops + 1, sizeof *mt->props)) {
        free(k);
        free(u);
        return HV_ERR_NOMEM;
    }
    mt->props[mt->nprops].key = k;
    mt->props[mt->nprops].unit = u;
    mt->props[mt->nprops].value = value;
    ++mt->nprops;
    return HV_OK;
}

int hv_material_property(const hv_material_table *t, int m, const char *key, double *value,
                         const char **unit)
{
    if (m < 0 || m >= t->n) return 0;
    const material *mt = &t->mats[m];
    for (int i = 0; i < mt->nprops; ++i)
        if (strcmp(mt->props[i].key, key) == 0) {
            if (value) *value = mt->props[i].value;
            if (unit) *unit = mt->props[i].unit;
            return 1;
        }
    return 0;
}

int hv_material_property_count(const hv_material_table *t, int m)
{
    return m >= 0 && m < t->n ? t->mats[m].nprops : 0;
}

const char *hv_material_property_key(const hv_material_table *t, int m, int i)
{
    if (m < 0 || m >= t->n || i < 0 || i >= t->mats[m].nprops) return NULL;
    return t->mats[m].props[i].key;
}

hv_status hv_material_table_clone(const hv_material_table *t, hv_material_table **out)
{
    char *json;
    hv_status s = hv_material_table_to_json(t, &json);
    if (s != HV_OK) return s;
    s = hv_material_table_from_json(json, out);
    free(json);
    return s;
}

json_t *hv_material_table_to_doc(const hv_material_table *t)
{
    json_t *mats = json_array();
    int failed = !mats;
    for (int i = 0; i < t->n && !failed; ++i) {
        const material *m = &t->mats[i];
        json_t *color = json_array(), *props = json_object();
        failed = !color || !props;
        for (int k = 0; k < 4 && !failed; ++k) failed = json_array_append_new(color, hv_json_float(m->rgba[k])) != 0;
        for (int p = 0; p < m->nprops && !failed; ++p)
            failed = hv_json_set(props, m->props[p].key,
                                 json_pack("{s:o, s:o}", "value", hv_json_number(m->props[p].value), "unit",
                                           hv_json_text(m->props[p].unit)));
        if (failed) {
            json_decref(color);
            json_decref(props);
        } else {
            failed = json_array_append_new(mats, json_pack("{s:o, s:o, s:o}", "name", hv_json_text(m->name), "color",
                                                           color, "properties", props)) != 0;
        }
    }
    if (failed) {
        json_decref(mats);
        return NULL;
    }
    return json_pack("{s:o}", "materials", mats);
}

hv_status hv_material_table_from_doc(const json_t *doc, const char *what, hv_material_table **out)
{
    *out = NULL;
    const json_t *mats;
    hv_status s = hv_json_need(doc, "materials", JSON_ARRAY, what, &mats);
    hv_material_table *t = NULL;
    if (s == HV_OK) s = hv_material_table_create(&t);
    for (size_t i = 0; s == HV_OK && i < json_array_size(mats); ++i) {
        const json_t *m = json_array_get(mats, i);
        char place[300];
        snprintf(place, sizeof place, "%s: materials[%zu]", what, i);
        const char *name;
        float rgba[4] = {0.5f, 0.5f, 0.5f, 1.0f};
        if ((s = hv_json_get_string(m, "name", place, &name)) != HV_OK) break;
        const json_t *color = json_object_get(m, "color");
        if (color) {
            double c[4] = {0, 0, 0, 1};
            size_t n = json_array_size(color) == 3 ? 3 : 4;
            if ((s = hv_json_get_numbers(m, "color", place, c, n)) != HV_OK) break;
            for (int k = 0; k < 4; ++k) rgba[k] = (float)c[k];
        }
        int mi;
        if ((s = hv_material_add(t, name, rgba, &mi)) != HV_OK) {
            s = hv_error_prefix(s == HV_ERR_INVALID ? HV_ERR_BAD_INPUT : s, "%s: ", place);
            break;
        }
        const json_t *props = json_object_get(m, "properties");
        if (props && !json_is_object(props)) {
            s = hv_error_set(HV_ERR_BAD_INPUT, "%s: properties is not an object", place);
            break;
        }
        const char *key;
        const json_t *p;
        json_object_foreach((json_t *)props, key, p) {
            char pp[400];
            snprintf(pp, sizeof pp, "%s: properties: %s", place, key);
            double value;
            const char *unit = "";
            if ((s = hv_json_get_number(p, "value", pp, &value)) != HV_OK) break;
            if (json_object_get(p, "unit") && (s = hv_json_get_string(p, "unit", pp, &unit)) != HV_OK) break;
            if ((s = hv_material_set_property(t, mi, key, value, unit)) != HV_OK) {
                s = hv_error_prefix(s == HV_ERR_INVALID ? HV_ERR_BAD_INPUT : s, "%s: ", place);
                break;
            }
        }
    }
    if (s != HV_OK) {
        hv_material_table_destroy(t);
        return s;
    }
    *out = t;
    return HV_OK;
}

hv_status hv_material_table_to_json(const hv_material_table *t, char **json)
{
    json_t *doc = hv_material_table_to_doc(t);
    *json = doc ? hv_schema_doc_dump(HV_DOC_MATERIALS, doc) : NULL;
    json_decref(doc);
    return *json ? HV_OK : hv_error_set(HV_ERR_NOMEM, "out of memory (writing the material table)");
}

hv_status hv_material_table_from_json(const char *json, hv_material_table **out)
{
    *out = NULL;
    json_t *doc;
    hv_status s = hv_schema_doc_parse(HV_DOC_MATERIALS, json, strlen(json), &doc);
    if (s == HV_OK) s = hv_material_table_from_doc(doc, hv_schema_key(HV_DOC_MATERIALS), out);
    json_decref(doc);
    return s;
}

hv_status hv_material_table_load(const hv_volume *vol, hv_material_table **out)
{
    *out = NULL;
    const char *json = hv_volume_meta_string(vol, hv_schema_key(HV_DOC_MATERIALS));
    if (!json)
        return hv_error_set(HV_ERR_NOT_FOUND,
                            "model has no materials: grade it first (hovox grade)");
    hv_material_table *t;
    hv_status s = hv_material_table_from_json(json, &t);
    if (s != HV_OK) return s;
    for (int m = 0; m < t->n; ++m)
        if (hv_material_grid(vol, t, m) < 0) {
            s = hv_error_set(HV_ERR_BAD_INPUT, "material '%s' has no float grid 'material.%s'",
                             t->mats[m].name, t->mats[m].name);
            hv_material_table_destroy(t);
            return s;
        }
    *out = t;
    return HV_OK;
}

hv_status hv_material_table_store(hv_volume *vol, const hv_material_table *t)
{
    char *json;
    hv_status s = hv_material_table_to_json(t, &json);
    if (s != HV_OK) return s;
    s = hv_volume_meta_set_string(vol, hv_schema_key(HV_DOC_MATERIALS), json);
    free(json);
    return s;
}

int hv_material_grid(const hv_volume *vol, const hv_material_table *t, int m)
{
    if (m < 0 || m >= t->n) return -1;
    char name[80];
    snprintf(name, sizeof name, "material.%s", t->mats[m].name);
    int g = hv_volume_grid_find(vol, name);
    return g >= 0 && hv_volume_grid_type(vol, g) == HV_GRID_FLOAT ? g : -1;
}

hv_status hv_composition_check(const double *p, int m, const char *what)
{
    char vec[512];
    size_t at = 0;
    at += (size_t)snprintf(vec, sizeof vec, "[");
    for (int i = 0; i < m && at < sizeof vec - 16; ++i)
        at += (size_t)snprintf(vec + at, sizeof vec - at, i ? ", %g" : "%g", p[i]);
    snprintf(vec + at, sizeof vec - at, "]");
    double sum = 0;
    for (int i = 0; i < m; ++i) {
        if (!isfinite(p[i]))
            return hv_error_set(HV_ERR_INVALID, "%s = %s: entry %d is not a number", what, vec, i + 1);
        if (p[i] < 0)
            return hv_error_set(HV_ERR_INVALID, "%s = %s: entry %d is negative (%g)", what, vec, i + 1, p[i]);
        sum += p[i];
    }
    if (fabs(sum - 1.0) > 1e-6)
        return hv_error_set(HV_ERR_INVALID, "%s = %s sums to %.9g, not 1 (Wu eq. 12)", what, vec, sum);
    return HV_OK;
}

void hv_model_probe(hv_accessor *acc, const hv_material_table *t, const int *grids,
                    const double p[3], int *inside, double *fractions)
{
    int m = t->n;
    float f[HV_MAX_MATERIALS], cov = 0;
    hv_volume_sample(acc, grids, m, p, f, &cov);
    for (int i = 0; i < m; ++i) fractions[i] = (double)f[i];
    *inside = cov >= 0.5f;
}
