/* src/export/properties.c - physical properties of mixtures: the Voigt rule of mixtures and
 * the Reuss inverse rule (Voigt 1889, Reuss 1929: the iso-strain and iso-stress bounds), and
 * measured linearization tables, property = f(fraction of one material), the step the
 * subdivision-gradients seed names as missing ("print targets with different material
 * mixtures and measure their stiffness ... interpolating between the samples"). */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/export.h"

#define MAX_SAMPLES 100000
#define MAX_CSV_BYTES ((size_t)16 << 20)

double hv_property_voigt(const double *p, const double *x, int m)
{
    double s = 0;
    for (int j = 0; j < m; ++j) s += p[j] * x[j];
    return s;
}

double hv_property_reuss(const double *p, const double *x, int m)
{
    double s = 0;
    for (int j = 0; j < m; ++j) {
        if (p[j] == 0) continue;
        /* a phase with no stiffness carries no stress: the series arrangement has none */
        if (!(x[j] > 0)) return 0;
        s += p[j] / x[j];
    }
    return s > 0 ? 1.0 / s : 0;
}

/* ---- linearization tables --------------------------------------------------------------- */

struct hv_linearization {
    char *property, *unit, *material;
    int n;
    double *x, *v;
};

static int valid_name(const char *s, size_t max, int allow_dot)
{
    size_t n = s ? strlen(s) : 0;
    if (n == 0 || n > max) return 0;
    for (size_t i = 0; i < n; ++i) {
        unsigned char c = (unsigned char)s[i];
        if (!(isalnum(c) || c == '_' || c == '-' || (allow_dot && c == '.'))) return 0;
    }
    return 1;
}

void hv_linearization_destroy(hv_linearization *lin)
{
    if (!lin) return;
    free(lin->property);
    free(lin->unit);
    free(lin->material);
    free(lin->x);
    free(lin->v);
    free(lin);
}

/* Check samples; on failure record HV_ERR_INVALID "<where>N: ..." (where = "sample " or a
 * caller's "name: line " form through line numbers). */
static hv_status check_samples(const double *x, const double *v, int n, const int *lines,
                               const char *where, hv_status code)
{
    if (n < 2) return hv_error_set(code, "%sneeds at least 2 samples (got %d)", where, n);
    if (n > MAX_SAMPLES)
        return hv_error_set(code, "%smore than %d samples (%d)", where, MAX_SAMPLES, n);
    for (int i = 0; i < n; ++i) {
        int at = lines ? lines[i] : i + 1;
        const char *what = lines ? "line" : "sample";
        if (!isfinite(x[i]) || !isfinite(v[i]))
            return hv_error_set(code, "%s%s %d: value is not a finite number", where, what, at);
        if (x[i] < 0 || x[i] > 1)
            return hv_error_set(code, "%s%s %d: fraction %g is outside [0, 1]", where, what, at,
                                x[i]);
        if (i > 0 && !(x[i] > x[i - 1]))
            return hv_error_set(code, "%s%s %d: fraction %g is not greater than the previous (%g)",
                                where, what, at, x[i], x[i - 1]);
    }
    return HV_OK;
}

static hv_status make(const char *property, const char *unit, const char *material,
                      const double *x, const double *v, int n, hv_linearization **out)
{
    hv_linearization *lin = hv_calloc(1, sizeof *lin);
    if (!lin) return HV_ERR_NOMEM;
    lin->property = hv_strdup(property);
    lin->unit = hv_strdup(unit ? unit : "");
    lin->material = hv_strdup(material);
    lin->x = hv_malloc_array((size_t)n, sizeof(double));
    lin->v = hv_malloc_array((size_t)n, sizeof(double));
    if (!lin->property || !lin->unit || !lin->material || !lin->x || !lin->v) {
        hv_linearization_destroy(lin);
        return HV_ERR_NOMEM;
    }
    memcpy(lin->x, x, (size_t)n * sizeof(double));
    memcpy(lin->v, v, (size_t)n * sizeof(double));
    lin->n = n;
    *out = lin;
    return HV_OK;
}

hv_status hv_linearization_create(const char *property, const char *unit, const char *material,
                                  const double *x, const double *value, int n,
                                  hv_linearization **out)
{
    *out = NULL;
    if (!valid_name(property, 64, 0))
        return hv_error_set(HV_ERR_INVALID, "linearization: property '%s' is not 1-64 characters "
                            "of [A-Za-z0-9_-]", property ? property : "(null)");
    if (!valid_name(material, 64, 0))
        return hv_error_set(HV_ERR_INVALID, "linearization: material '%s' is not 1-64 characters "
                            "of [A-Za-z0-9_-]", material ? material : "(null)");
    if (unit && (strlen(unit) > 32 || strpbrk(unit, "[],\n\r")))
        return hv_error_set(HV_ERR_INVALID, "linearization: unit '%s' is longer than 32 bytes or "
                            "holds one of [],", unit);
    char where[96];
    snprintf(where, sizeof where, "linearization of %s: ", property);
    hv_status s = check_samples(x, value, n, NULL, where, HV_ERR_INVALID);
    if (s != HV_OK) return s;
    return make(property, unit, material, x, value, n, out);
}

static int first_is_fraction(const char *a) { return strncmp(a, "fraction.", 9) == 0 && valid_name(a + 9, 64, 0); }

hv_status hv_linearization_parse(const char *text, size_t len, const char *name,
                                 const char *property, hv_linearization **out)
{
    *out = NULL;
    const hv_csv_table_form form = {name ? name : "linearization", first_is_fraction,
                                    "'fraction.<material>,<property>[<unit>]'", "fraction", MAX_SAMPLES};
    hv_csv_table c;
    hv_status s = hv_csv_table_parse(text, len, &form, &c);
    if (s != HV_OK) return s;
    if (property && strcmp(property, c.property) != 0)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: the table is for '%s', not '%s'", form.name,
                         c.header_line, c.property, property);
    if (s == HV_OK) {
        char where[600];
        snprintf(where, sizeof where, "%s: ", form.name);
        s = check_samples(c.x, c.v, (int)c.n, c.lines, where, HV_ERR_BAD_INPUT);
    }
    if (s == HV_OK) s = make(c.property, c.unit, c.first + 9, c.x, c.v, (int)c.n, out);
    hv_csv_table_free(&c);
    return s;
}

hv_status hv_linearization_load(const char *path, const char *property, hv_linearization **out)
{
    *out = NULL;
    char *data;
    size_t size;
    hv_status s = hv_read_file(path, MAX_CSV_BYTES, &data, &size);
    if (s == HV_OK) hv_input_note(path);
    if (s != HV_OK) return s;
    s = hv_linearization_parse(data, size, path, property, out);
    free(data);
    return s;
}

double hv_linearization_eval(const hv_linearization *lin, double x)
{
    const double *xs = lin->x, *vs = lin->v;
    int n = lin->n;
    if (!(x > xs[0])) return vs[0]; /* also NaN */
    if (x >= xs[n - 1]) return vs[n - 1];
    int lo = 0, hi = n - 1; /* xs[lo] < x < xs[hi] */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (xs[mid] <= x) lo = mid;
        else hi = mid;
    }
    double t = (x - xs[lo]) / (xs[hi] - xs[lo]);
    return vs[lo] + t * (vs[hi] - vs[lo]);
}

hv_status hv_linearization_invert(const hv_linearization *lin, double value, double *x)
{
    const double *xs = lin->x, *vs = lin->v;
    int n = lin->n;
    int up = vs[1] > vs[0];
    for (int i = 1; i < n; ++i)
        if (up ? !(vs[i] > vs[i - 1]) : !(vs[i] < vs[i - 1]))
            return hv_error_set(HV_ERR_INVALID, "linearization of %s: values are not strictly "
                                "monotonic (samples %d and %d), so the inverse is ambiguous",
                                lin->property, i, i + 1);
    double vmin = up ? vs[0] : vs[n - 1], vmax = up ? vs[n - 1] : vs[0];
    if (!(value >= vmin && value <= vmax))
        return hv_error_set(HV_ERR_INVALID, "linearization of %s: %g is outside the sampled "
                            "range [%g, %g]", lin->property, value, vmin, vmax);
    for (int i = 1; i < n; ++i) {
        double a = vs[i - 1], b = vs[i];
        if ((value >= a && value <= b) || (value <= a && value >= b)) {
            double t = (value - a) / (b - a);
            *x = xs[i - 1] + t * (xs[i] - xs[i - 1]);
            return HV_OK;
        }
    }
    *x = xs[n - 1];
    return HV_OK;
}

const char *hv_linearization_property(const hv_linearization *lin) { return lin->property; }
const char *hv_linearization_unit(const hv_linearization *lin) { return lin->unit; }
const char *hv_linearization_material(const hv_linearization *lin) { return lin->material; }
int hv_linearization_count(const hv_linearization *lin) { return lin->n; }
