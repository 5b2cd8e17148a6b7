/* src/colour/lut.c - lookup tables from data values to materials or colours (hovox/lut.h, issue
 * 30): read through the project's CSV row reader (core/csv_table.c), checked row by row (every
 * refusal names the file, the line and the value), evaluated by linear interpolation between
 * rows; and a scan's model painted from them at its voxel centres. A parser of files from
 * others: fuzzed (tests/fuzz/fuzz_lut.c). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/lut.h"
#include "hovox/material.h"
#include "io/scan/scan_internal.h"

#define MAX_LUT_BYTES (16u << 20)

struct hv_lut {
    hv_lut_kind kind;
    char value_name[33];
    int cols;                 /* materials, or 4 (RGBA) */
    char names[HV_MAX_MATERIALS][65];
    size_t n;
    double *x;                /* n values, rising */
    float *v;                 /* n * cols */
};

typedef struct lut_ctx {
    hv_lut *t;
    const char *name;
    int header_line;
    size_t cap;
    int lines[2]; /* the previous row's line */
} lut_ctx;

static int name_ok(const char *s, size_t max)
{
    size_t n = strlen(s);
    return n >= 1 && n <= max &&
           strspn(s, "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-") == n;
}

static int number(const char *s, double *v)
{
    char *end;
    errno = 0;
    *v = strtod(s, &end);
    return end != s && *end == '\0' && errno != ERANGE && isfinite(*v);
}

static hv_status header(lut_ctx *c, int line, char **field, int n, const char *raw)
{
    hv_lut *t = c->t;
    c->header_line = line;
    if (n < 2)
        return hv_error_set(HV_ERR_BAD_INPUT,
                            "%s: line %d: header '%s' needs a value name and at least one material or 'colour'",
                            c->name, line, raw);
    if (!name_ok(field[0], 32))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: value name '%.40s' is not 1-32 characters of [A-Za-z0-9_-]",
                            c->name, line, field[0]);
    snprintf(t->value_name, sizeof t->value_name, "%s", field[0]);
    if (n == 2 && (strcmp(field[1], "colour") == 0 || strcmp(field[1], "color") == 0)) {
        t->kind = HV_LUT_COLOUR;
        t->cols = 4;
        return HV_OK;
    }
    if (n - 1 > HV_MAX_MATERIALS)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: %d materials, at most %d", c->name, line, n - 1,
                            HV_MAX_MATERIALS);
    t->kind = HV_LUT_MATERIALS;
    t->cols = n - 1;
    for (int k = 0; k < t->cols; ++k) {
        const char *m = field[k + 1];
        if (!name_ok(m, 64))
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: material '%.70s' is not 1-64 characters of "
                                "[A-Za-z0-9_-]", c->name, line, m);
        for (int j = 0; j < k; ++j)
            if (strcmp(t->names[j], m) == 0)
                return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: material '%s' twice", c->name, line, m);
        snprintf(t->names[k], sizeof t->names[k], "%s", m);
    }
    return HV_OK;
}

/* One row's columns into out[cols]. */
static hv_status row_values(lut_ctx *c, int line, char **field, float *out)
{
    hv_lut *t = c->t;
    if (t->kind == HV_LUT_COLOUR) {
        const char *s = field[1];
        size_t len = strlen(s);
        float rgba[4];
        if (s[0] != '#' || (len != 7 && len != 9) || strspn(s + 1, "0123456789abcdefABCDEF") != len - 1 ||
            hv_color_parse(s, rgba) != HV_OK) {
            hv_error_clear();
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: colour '%.40s' is not #rrggbb or #rrggbbaa", c->name,
                                line, s);
        }
        memcpy(out, rgba, sizeof rgba);
        return HV_OK;
    }
    double sum = 0;
    for (int k = 0; k < t->cols; ++k) {
        double f;
        if (!number(field[k + 1], &f) || f < 0 || f > 1)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: %s fraction '%.40s' is not a number in [0, 1]",
                                c->name, line, t->names[k], field[k + 1]);
        out[k] = (float)f;
        sum += f;
    }
    if (fabs(sum - 1) > 1e-4)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: fractions sum to %.6g, not 1", c->name, line, sum);
    return HV_OK;
}

static hv_status lut_row(void *user, int line, char **field, int n, const char *raw)
{
    lut_ctx *c = user;
    hv_lut *t = c->t;
    if (!c->header_line) return header(c, line, field, n, raw);
    if (t->kind == HV_LUT_COLOUR && n != 2)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: expected 2 fields (%s and a colour), got %d", c->name,
                            line, t->value_name, n);
    if (t->kind == HV_LUT_MATERIALS && n != t->cols + 1)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: expected %d fields (%s and %d material%s), got %d",
                            c->name, line, t->cols + 1, t->value_name, t->cols, t->cols == 1 ? "" : "s", n);
    if (t->n >= HV_LUT_MAX_ROWS)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: more than %d rows", c->name, line, HV_LUT_MAX_ROWS);
    double x;
    if (!number(field[0], &x))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: %s '%.40s' is not a finite number", c->name, line,
                            t->value_name, field[0]);
    if (t->n && !(x > t->x[t->n - 1]))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: %s %.9g is not greater than line %d's (%.9g)", c->name,
                            line, t->value_name, x, c->lines[0], t->x[t->n - 1]);
    if (t->n == c->cap) {
        size_t cap = c->cap ? 2 * c->cap : 16;
        double *nx = hv_realloc(t->x, cap * sizeof *nx);
        if (!nx) return HV_ERR_NOMEM;
        t->x = nx;
        float *nv = hv_realloc(t->v, cap * (size_t)t->cols * sizeof *nv);
        if (!nv) return HV_ERR_NOMEM;
        t->v = nv;
        c->cap = cap;
    }
    hv_status s = row_values(c, line, field, t->v + t->n * (size_t)t->cols);
    if (s != HV_OK) return s;
    t->x[t->n++] = x;
    c->lines[0] = line;
    return HV_OK;
}

hv_status hv_lut_parse(const char *text, size_t len, const char *name, hv_lut **out)
{
    *out = NULL;
    hv_lut *t = hv_calloc(1, sizeof *t);
    if (!t) return HV_ERR_NOMEM;
    lut_ctx c = {t, name ? name : "lookup table", 0, 0, {0, 0}};
    hv_status s = hv_csv_each_row(text, len, c.name, lut_row, &c);
    if (s == HV_OK && !c.header_line)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: empty: no header line '<value name>,<materials...>' or "
                         "'<value name>,colour'", c.name);
    if (s == HV_OK && t->n == 0)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: a header and no rows", c.name, c.header_line);
    if (s != HV_OK) {
        hv_lut_destroy(t);
        return s;
    }
    *out = t;
    return HV_OK;
}

hv_status hv_lut_load(const char *path, hv_lut **out)
{
    *out = NULL;
    char *data;
    size_t size;
    hv_status s = hv_read_file(path, MAX_LUT_BYTES, &data, &size);
    if (s != HV_OK) return s;
    hv_input_note(path);
    s = hv_lut_parse(data, size, path, out);
    free(data);
    return s;
}

void hv_lut_destroy(hv_lut *t)
{
    if (!t) return;
    free(t->x);
    free(t->v);
    free(t);
}

hv_lut_kind hv_lut_kind_of(const hv_lut *t) { return t->kind; }
const char *hv_lut_value_name(const hv_lut *t) { return t->value_name; }
int hv_lut_columns(const hv_lut *t) { return t->cols; }
size_t hv_lut_rows(const hv_lut *t) { return t->n; }

const char *hv_lut_material(const hv_lut *t, int k)
{
    return t->kind == HV_LUT_MATERIALS && k >= 0 && k < t->cols ? t->names[k] : NULL;
}

void hv_lut_range(const hv_lut *t, double *lo, double *hi)
{
    *lo = t->x[0];
    *hi = t->x[t->n - 1];
}

void hv_lut_eval(const hv_lut *t, double value, float *out)
{
    size_t cols = (size_t)t->cols;
    if (!(value > t->x[0])) {
        memcpy(out, t->v, cols * sizeof *out);
        return;
    }
    if (value >= t->x[t->n - 1]) {
        memcpy(out, t->v + (t->n - 1) * cols, cols * sizeof *out);
        return;
    }
    size_t lo = 0, hi = t->n - 1; /* x[lo] < value < x[hi] */
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2;
        if (t->x[mid] <= value) lo = mid;
        else hi = mid;
    }
    double w = (value - t->x[lo]) / (t->x[hi] - t->x[lo]);
    const float *a = t->v + lo * cols, *b = t->v + hi * cols;
    for (size_t k = 0; k < cols; ++k) out[k] = (float)((1 - w) * a[k] + w * b[k]);
}

/* ---- painting a scan's model ------------------------------------------------------------------ */

typedef struct paint_ctx {
    const hv_scan_level *lv;
    const hv_lut *lut;
    hv_colour_map *map;
    const double *xyz;
    size_t n;
    int cols;
    float *val; /* cols grids of n */
} paint_ctx;

static hv_status paint_range(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    paint_ctx *c = vctx;
    for (size_t i = b; i < e; ++i) {
        double idx[3];
        hv_scan_level_index(c->lv, c->xyz + 3 * i, idx);
        for (int a = 0; a < 3; ++a) idx[a] = HV_CLAMP(idx[a], -0.5, (double)c->lv->n[a] - 0.5);
        double value = hv_scan_level_at_index(c->lv, idx); /* the iso-0 level: the value itself */
        float col[HV_MAX_MATERIALS];
        hv_lut_eval(c->lut, value, col);
        if (c->map) {
            uint8_t c8[4];
            for (int k = 0; k < 4; ++k) c8[k] = (uint8_t)lrintf(HV_CLAMP(col[k], 0.0f, 1.0f) * 255.0f);
            hv_colour_map_fractions(c->map, c8, col);
        }
        for (int k = 0; k < c->cols; ++k) c->val[(size_t)k * c->n + i] = col[k];
    }
    return HV_OK;
}

hv_status hv_lut_paint_scan(hv_volume *model, const hv_scan *scan, const hv_lut *lut, hv_colour_map *map,
                            uint64_t max_memory, const hv_progress *progress)
{
    if (!model || !scan || !lut) return hv_error_set(HV_ERR_INVALID, "hv_lut_paint_scan: NULL argument");
    int colour = lut->kind == HV_LUT_COLOUR;
    if (colour && !map) return hv_error_set(HV_ERR_INVALID, "a colour lookup table needs a colour map");
    int cols = colour ? HV_COLOUR_SLOTS : lut->cols;
    double *xyz = NULL;
    size_t n = 0;
    hv_status s = hv_volume_centres(model, "occupancy", &xyz, &n);
    if (s != HV_OK) return s;
    uint64_t need = (uint64_t)n * (24 + 4 * (uint64_t)cols * 2), budget = hv_memory_budget(max_memory);
    if (budget && need > budget) {
        char a[32], b[32];
        free(xyz);
        return hv_error_option(HV_ERR_LIMIT, "%s: materials for %llu voxels need about %s, more than the limit of %s "
                               "({max_memory})", hv_scan_name(scan), (unsigned long long)n,
                               hv_size_text(a, sizeof a, (double)need), hv_size_text(b, sizeof b, (double)budget));
    }
    float *val = hv_malloc_array(n ? n : 1, (size_t)cols * sizeof *val);
    hv_scan_shape shape = {.select = HV_SCAN_SELECT_ISO, .iso = 0};
    hv_scan_level lv;
    if (!val) s = HV_ERR_NOMEM;
    if (s == HV_OK) s = hv_scan_level_init(scan, &shape, &lv);
    if (s == HV_OK) {
        paint_ctx c = {&lv, lut, colour ? map : NULL, xyz, n, cols, val};
        s = hv_parallel_for(n, 4096, paint_range, &c, progress, "materials");
        hv_scan_level_free(&lv);
    }
    free(xyz);
    hv_material_table *tab = NULL;
    if (s == HV_OK) s = hv_material_table_create(&tab);
    for (int k = 0; k < cols && s == HV_OK; ++k)
        s = hv_material_add(tab, colour ? hv_colour_map_resin(map, k) : lut->names[k], NULL, NULL);
    for (int k = 0; k < cols && s == HV_OK; ++k) {
        char name[160];
        snprintf(name, sizeof name, "material.%s", colour ? hv_colour_map_resin(map, k) : lut->names[k]);
        s = hv_volume_grid_set(model, name, "occupancy", val + (size_t)k * n, n);
    }
    if (s == HV_OK) s = hv_material_table_store(model, tab);
    hv_material_table_destroy(tab);
    free(val);
    return s;
}

hv_status hv_lut_scan_model(const hv_scan *scan, const hv_scan_voxelize_options *opts, const hv_lut *lut,
                            hv_colour_map *map, hv_volume **out, hv_scan_voxelize_report *report)
{
    *out = NULL;
    hv_volume *vol = NULL;
    hv_status s = hv_scan_voxelize(scan, opts, &vol, report);
    if (s == HV_OK && lut) s = hv_lut_paint_scan(vol, scan, lut, map, opts->max_memory, opts->progress);
    if (s != HV_OK) {
        hv_volume_destroy(vol);
        return s;
    }
    *out = vol;
    return HV_OK;
}
