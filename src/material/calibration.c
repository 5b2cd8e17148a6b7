/* src/material/calibration.c - units and calibration tables: measured property values along a
 * grading source's composition path Ms -> Me (property(t), t in [0, 1]), piecewise linear,
 * strictly monotone so that a property target maps back to exactly one composition (the
 * design-by-property step PolyJet digital materials need: their stiffness is far from linear in
 * the fraction). */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/material.h"

#define MAX_ROWS 100000
#define MAX_CSV_BYTES ((size_t)16 << 20)

/* ---- units -------------------------------------------------------------------------------- */

static const struct {
    const char *unit, *si;
    double f;
} k_units[] = {
    {"Pa", "Pa", 1},          {"kPa", "Pa", 1e3},        {"MPa", "Pa", 1e6},      {"GPa", "Pa", 1e9},
    {"N/mm^2", "Pa", 1e6},    {"kg/m^3", "kg/m^3", 1},   {"kg/m3", "kg/m^3", 1},  {"g/cm^3", "kg/m^3", 1e3},
    {"g/cm3", "kg/m^3", 1e3}, {"g/cc", "kg/m^3", 1e3},   {"1", "1", 1},           {"-", "1", 1},
};

int hv_unit_si(const char *unit, const char **si, double *factor)
{
    *si = unit ? unit : "";
    *factor = 1;
    for (size_t i = 0; unit && i < HV_COUNT(k_units); ++i)
        if (strcmp(unit, k_units[i].unit) == 0) {
            *si = k_units[i].si;
            *factor = k_units[i].f;
            return 1;
        }
    return 0;
}

int hv_unit_convert(const char *from, const char *to, double *factor)
{
    from = from ? from : "";
    to = to ? to : "";
    *factor = 1;
    if (strcmp(from, to) == 0) return 1;
    const char *sa, *sb;
    double fa, fb;
    if (!hv_unit_si(from, &sa, &fa) || !hv_unit_si(to, &sb, &fb) || strcmp(sa, sb) != 0) return 0;
    *factor = fa / fb;
    return 1;
}

hv_status hv_quantity_parse(const char *text, const char *unit, const char *what, double *value)
{
    unit = unit ? unit : "";
    const char *s = text ? text : "";
    while (*s == ' ') ++s;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || errno == ERANGE || !isfinite(v))
        return hv_error_set(HV_ERR_INVALID, "%s = '%s' is not a number with an optional unit", what, text ? text : "");
    while (*end == ' ') ++end;
    char u[64];
    size_t n = strlen(end);
    while (n > 0 && end[n - 1] == ' ') --n;
    if (n >= sizeof u)
        return hv_error_set(HV_ERR_INVALID, "%s = '%s': the unit is longer than 63 bytes", what, text);
    memcpy(u, end, n);
    u[n] = '\0';
    double f = 1;
    if (n > 0 && !hv_unit_convert(u, unit, &f))
        return hv_error_set(HV_ERR_INVALID, "%s = '%s': unit %s does not convert to %s", what, text, u,
                            *unit ? unit : "the table's (it has no unit)");
    *value = v * f;
    return HV_OK;
}

/* ---- tables ------------------------------------------------------------------------------- */

struct hv_calibration {
    int refs;
    char property[65], unit[33];
    int n;
    double *t, *v;
};

static int valid_property(const char *s)
{
    size_t n = s ? strlen(s) : 0;
    if (n == 0 || n > 64) return 0;
    for (size_t i = 0; i < n; ++i) {
        unsigned char c = (unsigned char)s[i];
        if (!(isalnum(c) || c == '_' || c == '-')) return 0;
    }
    return 1;
}

static int valid_unit(const char *u) { return !u || (strlen(u) <= 32 && !strpbrk(u, "[],\n\r")); }

/* The rows' rule: at least 2, t strictly increasing in [0, 1], values finite and strictly
 * monotone (the direction set by the first two). `where` prefixes the message; rows are named
 * by lines[i] ("line N") or by their number ("row N"). */
static hv_status check_rows(const char *property, const double *t, const double *v, int n, const int *lines,
                            const char *where, hv_status code)
{
    const char *what = lines ? "line" : "row";
    if (n < 2) return hv_error_set(code, "%sneeds at least 2 rows (got %d)", where, n);
    if (n > MAX_ROWS) return hv_error_set(code, "%smore than %d rows (%d)", where, MAX_ROWS, n);
    int up = v[1] > v[0];
    for (int i = 0; i < n; ++i) {
        int at = lines ? lines[i] : i + 1, prev = i > 0 ? (lines ? lines[i - 1] : i) : 0;
        if (!isfinite(t[i])) return hv_error_set(code, "%s%s %d: t is not a finite number", where, what, at);
        if (!isfinite(v[i]))
            return hv_error_set(code, "%s%s %d: %s is not a finite number", where, what, at, property);
        if (t[i] < 0 || t[i] > 1)
            return hv_error_set(code, "%s%s %d: t = %g is outside [0, 1]", where, what, at, t[i]);
        if (i > 0 && !(t[i] > t[i - 1]))
            return hv_error_set(code, "%s%s %d: t = %g is not greater than %s %d's (%g)", where, what, at, t[i], what,
                                prev, t[i - 1]);
        if (i > 0 && (up ? !(v[i] > v[i - 1]) : !(v[i] < v[i - 1])))
            return hv_error_set(code, "%s%s %d: %s %.9g is not %s than %s %d's (%.9g): the values must be strictly "
                                "monotone", where, what, at, property, v[i], up ? "greater" : "less", what, prev,
                                v[i - 1]);
    }
    return HV_OK;
}

static hv_status make(const char *property, const char *unit, const double *t, const double *v, int n,
                      hv_calibration **out)
{
    hv_calibration *c = hv_calloc(1, sizeof *c);
    if (!c) return HV_ERR_NOMEM;
    c->refs = 1;
    snprintf(c->property, sizeof c->property, "%s", property);
    snprintf(c->unit, sizeof c->unit, "%s", unit ? unit : "");
    c->t = hv_malloc_array((size_t)n, sizeof(double));
    c->v = hv_malloc_array((size_t)n, sizeof(double));
    if (!c->t || !c->v) {
        hv_calibration_release(c);
        return HV_ERR_NOMEM;
    }
    memcpy(c->t, t, (size_t)n * sizeof(double));
    memcpy(c->v, v, (size_t)n * sizeof(double));
    c->n = n;
    *out = c;
    return HV_OK;
}

hv_status hv_calibration_create(const char *property, const char *unit, const double *t, const double *value, int n,
                                hv_calibration **out)
{
    *out = NULL;
    if (!valid_property(property))
        return hv_error_set(HV_ERR_INVALID, "calibration: property '%s' is not 1-64 characters of [A-Za-z0-9_-]",
                            property ? property : "(null)");
    if (!valid_unit(unit))
        return hv_error_set(HV_ERR_INVALID, "calibration of %s: unit '%s' is longer than 32 bytes or holds one of [],",
                            property, unit);
    char where[120];
    snprintf(where, sizeof where, "calibration of %s: ", property);
    hv_status s = check_rows(property, t, value, n, NULL, where, HV_ERR_INVALID);
    return s == HV_OK ? make(property, unit, t, value, n, out) : s;
}

hv_calibration *hv_calibration_retain(hv_calibration *c)
{
    if (c) __atomic_add_fetch(&c->refs, 1, __ATOMIC_RELAXED);
    return c;
}

void hv_calibration_release(hv_calibration *c)
{
    if (!c || __atomic_sub_fetch(&c->refs, 1, __ATOMIC_ACQ_REL) > 0) return;
    free(c->t);
    free(c->v);
    free(c);
}

/* ---- CSV ---------------------------------------------------------------------------------- */

static int first_is_t(const char *a) { return strcmp(a, "t") == 0; }

hv_status hv_calibration_parse(const char *text, size_t len, const char *name, hv_calibration **out)
{
    *out = NULL;
    const hv_csv_table_form form = {name ? name : "calibration", first_is_t,
"'t,<property>[<unit>]'", "t", MAX_ROWS};
    hv_csv_table c;
    hv_status s = hv_csv_table_parse(text, len, &form, &c);
    if (s != HV_OK) return s;
    char where[600];
    snprintf(where, sizeof where, "%s: ", form.name);
    s = check_rows(c.property, c.x, c.v, (int)c.n, c.lines, where, HV_ERR_BAD_INPUT);
    if (s == HV_OK) s = make(c.property, c.unit, c.x, c.v, (int)c.n, out);
    hv_csv_table_free(&c);
    return s;
}

hv_status hv_calibration_load(const char *path, hv_calibration **out)
{
    *out = NULL;
    char *data;
    size_t size;
    hv_status s = hv_read_file(path, MAX_CSV_BYTES, &data, &size);
    if (s == HV_OK) hv_input_note(path);
    if (s != HV_OK) return s;
    s = hv_calibration_parse(data, size, path, out);
    free(data);
    return s;
}

/* ---- evaluation ------------------------------------------------------------------------------ */

double hv_calibration_eval(const hv_calibration *c, double t)
{
    const double *ts = c->t, *vs = c->v;
    int n = c->n;
    if (!(t >= ts[0] && t <= ts[n - 1])) return NAN;
    if (t == ts[n - 1]) return vs[n - 1];
    int lo = 0, hi = n - 1; /* ts[lo] <= t < ts[hi] */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (ts[mid] <= t) lo = mid;
        else hi = mid;
    }
    double u = (t - ts[lo]) / (ts[hi] - ts[lo]);
    return vs[lo] + u * (vs[hi] - vs[lo]);
}

void hv_calibration_range(const hv_calibration *c, double *lo, double *hi)
{
    int up = c->v[c->n - 1] > c->v[0];
    if (lo) *lo = up ? c->v[0] : c->v[c->n - 1];
    if (hi) *hi = up ? c->v[c->n - 1] : c->v[0];
}

hv_status hv_calibration_invert(const hv_calibration *c, double value, double *t)
{
    double lo, hi;
    hv_calibration_range(c, &lo, &hi);
    if (!(value >= lo && value <= hi))
        return hv_error_set(HV_ERR_INVALID, "%s %.9g%s%s is outside the calibration's range [%.9g, %.9g]%s%s", c->property,
                            value, *c->unit ? " " : "", c->unit, lo, hi, *c->unit ? " " : "", c->unit);
    const double *ts = c->t, *vs = c->v;
    int n = c->n, up = vs[n - 1] > vs[0];
    /* the segment [i, i+1] whose values bracket `value`: binary search on the monotone values */
    int a = 0, b = n - 1;
    while (b - a > 1) {
        int mid = (a + b) / 2;
        if (up ? vs[mid] <= value : vs[mid] >= value) a = mid;
        else b = mid;
    }
    if (value == vs[a]) {
        *t = ts[a];
        return HV_OK;
    }
    if (value == vs[b]) {
        *t = ts[b];
        return HV_OK;
    }
    double u = (value - vs[a]) / (vs[b] - vs[a]);
    *t = ts[a] + u * (ts[b] - ts[a]);
    return HV_OK;
}

const char *hv_calibration_property(const hv_calibration *c) { return c->property; }
const char *hv_calibration_unit(const hv_calibration *c) { return c->unit; }
int hv_calibration_rows(const hv_calibration *c) { return c->n; }

void hv_calibration_row(const hv_calibration *c, int i, double *t, double *value)
{
    if (t) *t = c->t[i];
    if (value) *value = c->v[i];
}
