/* src/core/csv_table.c - CSV text cut into rows of trimmed fields (internal.h hv_csv_each_row),
 * and on it two-column tables (hv_csv_table_parse): a header line and rows "x,value", as read by calibration tables (material/calibration.c, "t,<property>")
 * and linearization tables (export/properties.c, "fraction.<material>,<property>"). One
 * reader, so both refuse the same damaged text with the same words; each checks its header. The
 * lookup tables of scans (src/colour/lut.c) read their rows with hv_csv_each_row too. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"

static char *trim(char *s)
{
    while (*s == ' ' || *s == '\t') ++s;
    size_t n = strlen(s);
    while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\r')) s[--n] = '\0';
    return s;
}

static int parse_number(const char *s, double *v)
{
    char *end;
    errno = 0;
    *v = strtod(s, &end);
    return end != s && *end == '\0' && errno != ERANGE && isfinite(*v);
}

/* "<property>" or "<property>[<unit>]": property 1-64 of [A-Za-z0-9_-], unit at most 32 bytes */
static int split_property(char *b, hv_csv_table *t)
{
    char *br = strchr(b, '[');
    t->unit[0] = '\0';
    if (br) {
        size_t n = strlen(br);
        if (n < 2 || br[n - 1] != ']' || n - 2 > 32 || memchr(br + 1, '[', n - 2) || memchr(br + 1, ']', n - 2))
            return 0;
        snprintf(t->unit, sizeof t->unit, "%.*s", (int)(n - 2), br + 1);
        *br = '\0';
        b = trim(b);
    }
    size_t n = strlen(b);
    if (n < 1 || n > 64 || strspn(b, "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-") != n) return 0;
    snprintf(t->property, sizeof t->property, "%s", b);
    return 1;
}

static hv_status add_row(hv_csv_table *t, size_t *cap, double x, double v, int line)
{
    if (t->n == *cap) {
        size_t c = *cap ? 2 * *cap : 64;
        double *nx = hv_realloc(t->x, c * sizeof *nx);
        if (!nx) return HV_ERR_NOMEM;
        t->x = nx;
        double *nv = hv_realloc(t->v, c * sizeof *nv);
        if (!nv) return HV_ERR_NOMEM;
        t->v = nv;
        int *nl = hv_realloc(t->lines, c * sizeof *nl);
        if (!nl) return HV_ERR_NOMEM;
        t->lines = nl;
        *cap = c;
    }
    t->x[t->n] = x;
    t->v[t->n] = v;
    t->lines[t->n++] = line;
    return HV_OK;
}

hv_status hv_csv_each_row(const char *text, size_t len, const char *name, hv_csv_row_fn fn, void *user)
{
    char *buf = hv_malloc(len + 1);
    if (!buf) return HV_ERR_NOMEM;
    memcpy(buf, text, len);
    buf[len] = '\0';
    hv_status s = HV_OK;
    int line = 0;
    if (strlen(buf) != len) {
        int at = 1;
        for (size_t i = 0; i < strlen(buf); ++i) at += buf[i] == '\n';
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: NUL byte in text", name, at);
    }
    for (char *p = buf; s == HV_OK && *p;) {
        char *nl = strchr(p, '\n');
        if (nl) *nl = '\0';
        ++line;
        char *l = trim(p), raw[160], *field[HV_CSV_MAX_FIELDS];
        p = nl ? nl + 1 : p + strlen(p);
        if (*l == '\0' || *l == '#') continue;
        snprintf(raw, sizeof raw, "%s", l);
        int n = 0;
        for (char *f = l;; ++n) {
            char *comma = strchr(f, ',');
            if (n == HV_CSV_MAX_FIELDS) {
                s = hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: more than %d comma-separated fields", name, line,
                                 HV_CSV_MAX_FIELDS);
                break;
            }
            if (comma) *comma = '\0';
            field[n] = trim(f);
            if (!comma) {
                ++n;
                break;
            }
            f = comma + 1;
        }
        if (s == HV_OK) s = fn(user, line, field, n, raw);
    }
    free(buf);
    return s;
}

typedef struct table_ctx {
    const hv_csv_table_form *form;
    hv_csv_table *t;
    size_t cap;
} table_ctx;

static hv_status table_row(void *user, int line, char **field, int n, const char *raw)
{
    table_ctx *c = user;
    const hv_csv_table_form *form = c->form;
    hv_csv_table *t = c->t;
    if (n != 2)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: expected 2 comma-separated fields, got '%s'", form->name,
                            line, raw);
    char *a = field[0], *b = field[1];
    double x, v;
    if (!t->header_line) {
        snprintf(t->first, sizeof t->first, "%s", a);
        t->header_line = line;
        if (strlen(a) >= sizeof t->first || !form->first_ok(a) || !split_property(b, t))
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: header '%s' is not %s (property: 1-64 characters "
                                "of [A-Za-z0-9_-]; unit: at most 32 bytes)", form->name, line, raw, form->header);
        return HV_OK;
    }
    if (!parse_number(a, &x))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: %s '%s' is not a finite number", form->name, line,
                            form->xname, a);
    if (!parse_number(b, &v))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: %s '%s' is not a finite number", form->name, line,
                            t->property, b);
    if (t->n >= (size_t)form->max_rows)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: more than %d rows", form->name, line, form->max_rows);
    return add_row(t, &c->cap, x, v, line);
}

hv_status hv_csv_table_parse(const char *text, size_t len, const hv_csv_table_form *form, hv_csv_table *t)
{
    memset(t, 0, sizeof *t);
    table_ctx c = {form, t, 0};
    hv_status s = hv_csv_each_row(text, len, form->name, table_row, &c);
    if (s == HV_OK && !t->header_line)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: empty: no header line %s", form->name, form->header);
    if (s == HV_OK && t->n == 0)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: a header and no rows (at least 2 are needed)", form->name,
                         t->header_line);
    if (s != HV_OK) hv_csv_table_free(t);
    return s;
}

void hv_csv_table_free(hv_csv_table *t)
{
    free(t->x);
    free(t->v);
    free(t->lines);
    t->x = t->v = NULL;
    t->lines = NULL;
    t->n = 0;
}
