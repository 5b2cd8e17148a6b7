/* src/material/dfn.c - distribution functions f(d) on [0, dg] (Wu 2.2: "any analytical,
 * segmental, linear or nonlinear functions"): linear, sine, power, smoothstep, piecewise-linear
 * tables, expressions and callbacks. They are only ever sampled into an AGS's table. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "material_internal.h"

enum { F_LINEAR, F_SINE, F_POWER, F_SMOOTH, F_TABLE, F_EXPR, F_CALL };

struct hv_dfn {
    int kind;
    double p[4];
    double *td, *tf;
    int tn;
    hv_expr *expr;
    hv_dfn_callback fn;
    void *user;
    char desc[256];
};

static hv_status make(int kind, hv_dfn **out)
{
    *out = hv_calloc(1, sizeof **out);
    if (!*out) return HV_ERR_NOMEM;
    (*out)->kind = kind;
    return HV_OK;
}

static int finite_all(const double *v, int n)
{
    for (int i = 0; i < n; ++i)
        if (!isfinite(v[i])) return 0;
    return 1;
}

hv_status hv_dfn_linear(double a, double b, hv_dfn **out)
{
    double v[2] = {a, b};
    if (!finite_all(v, 2)) return hv_error_set(HV_ERR_INVALID, "linear f: coefficients must be finite");
    hv_status s = make(F_LINEAR, out);
    if (s != HV_OK) return s;
    (*out)->p[0] = a;
    (*out)->p[1] = b;
    snprintf((*out)->desc, sizeof (*out)->desc, "linear(%.9g, %.9g)", a, b);
    return HV_OK;
}

hv_status hv_dfn_sine(double k, double amp, double phase, double offset, hv_dfn **out)
{
    double v[4] = {k, amp, phase, offset};
    if (!finite_all(v, 4)) return hv_error_set(HV_ERR_INVALID, "sine f: parameters must be finite");
    hv_status s = make(F_SINE, out);
    if (s != HV_OK) return s;
    memcpy((*out)->p, v, sizeof v);
    snprintf((*out)->desc, sizeof (*out)->desc, "sine(k=%.9g, amplitude=%.9g, phase=%.9g, offset=%.9g)",
             k, amp, phase, offset);
    return HV_OK;
}

hv_status hv_dfn_power(double p, hv_dfn **out)
{
    if (!(p > 0) || !isfinite(p)) return hv_error_set(HV_ERR_INVALID, "power f: exponent %g must be > 0", p);
    hv_status s = make(F_POWER, out);
    if (s != HV_OK) return s;
    (*out)->p[0] = p;
    snprintf((*out)->desc, sizeof (*out)->desc, "power(%.9g)", p);
    return HV_OK;
}

hv_status hv_dfn_smoothstep(hv_dfn **out)
{
    hv_status s = make(F_SMOOTH, out);
    if (s == HV_OK) snprintf((*out)->desc, sizeof (*out)->desc, "smoothstep");
    return s;
}

hv_status hv_dfn_table(const double *d, const double *f, int n, hv_dfn **out)
{
    *out = NULL;
    if (n < 2) return hv_error_set(HV_ERR_INVALID, "table f: needs at least 2 points (got %d)", n);
    for (int i = 0; i < n; ++i) {
        if (!isfinite(d[i]) || !isfinite(f[i]))
            return hv_error_set(HV_ERR_INVALID, "table f: point %d (%g, %g) is not finite", i + 1, d[i], f[i]);
        if (i && !(d[i] > d[i - 1]))
            return hv_error_set(HV_ERR_INVALID,
                                "table f: distances must increase; point %d has d = %g after %g",
                                i + 1, d[i], d[i - 1]);
    }
    hv_status s = make(F_TABLE, out);
    if (s != HV_OK) return s;
    hv_dfn *t = *out;
    t->td = hv_malloc_array((size_t)n, sizeof(double));
    t->tf = hv_malloc_array((size_t)n, sizeof(double));
    if (!t->td || !t->tf) {
        hv_dfn_destroy(t);
        *out = NULL;
        return HV_ERR_NOMEM;
    }
    memcpy(t->td, d, (size_t)n * sizeof(double));
    memcpy(t->tf, f, (size_t)n * sizeof(double));
    t->tn = n;
    snprintf(t->desc, sizeof t->desc, "table(%d points, d %.6g..%.6g)", n, d[0], d[n - 1]);
    return HV_OK;
}

hv_status hv_dfn_expr(const char *text, hv_dfn **out)
{
    *out = NULL;
    hv_expr *e;
    hv_status s = hv_expr_parse(text, &e);
    if (s != HV_OK) return hv_error_prefix(s, "f = '%s': ", text);
    s = make(F_EXPR, out);
    if (s != HV_OK) {
        hv_expr_free(e);
        return s;
    }
    (*out)->expr = e;
    snprintf((*out)->desc, sizeof (*out)->desc, "%s", text);
    return HV_OK;
}

hv_status hv_dfn_function(hv_dfn_callback fn, void *user, const char *description, hv_dfn **out)
{
    if (!fn) return hv_error_set(HV_ERR_INVALID, "function f: no callback");
    hv_status s = make(F_CALL, out);
    if (s != HV_OK) return s;
    (*out)->fn = fn;
    (*out)->user = user;
    snprintf((*out)->desc, sizeof (*out)->desc, "%s", description ? description : "function");
    return HV_OK;
}

void hv_dfn_destroy(hv_dfn *f)
{
    if (!f) return;
    free(f->td);
    free(f->tf);
    hv_expr_free(f->expr);
    free(f);
}

double hv_dfn_eval(const hv_dfn *f, double d, double dg)
{
    double t = dg > 0 ? d / dg : 0.0;
    switch (f->kind) {
    case F_LINEAR: return f->p[0] * d + f->p[1];
    case F_SINE: return f->p[1] * sin(f->p[0] * d + f->p[2]) + f->p[3];
    case F_POWER: return pow(HV_CLAMP(t, 0.0, 1.0), f->p[0]);
    case F_SMOOTH: {
        double u = HV_CLAMP(t, 0.0, 1.0);
        return u * u * (3.0 - 2.0 * u);
    }
    case F_TABLE: {
        if (d <= f->td[0]) return f->tf[0];
        if (d >= f->td[f->tn - 1]) return f->tf[f->tn - 1];
        int lo = 0, hi = f->tn - 1;
        while (hi - lo > 1) {
            int mid = (lo + hi) / 2;
            if (f->td[mid] <= d) lo = mid;
            else hi = mid;
        }
        double u = (d - f->td[lo]) / (f->td[hi] - f->td[lo]);
        return f->tf[lo] + u * (f->tf[hi] - f->tf[lo]);
    }
    case F_EXPR: return hv_expr_eval(f->expr, d, dg);
    case F_CALL: return f->fn(f->user, d);
    }
    return NAN;
}

const char *hv_dfn_describe(const hv_dfn *f) { return f->desc; }

/* ---- f as a kind with parameters (hv_dfn_option_set) ------------------------------------------ */

static const char *const k_kind_names[] = {"linear", "sine", "power", "smoothstep", "table", NULL};
static const hv_enum_def k_kind = {"f kind", k_kind_names, NULL, NULL};

#define DOFF(f) offsetof(hv_dfn_options, f)
static const hv_option k_dfn_opts[] = {
    {.key = "kind", .kind = HV_OPT_ENUM, .flags = HV_OPT_REQUIRED, .offset = DOFF(kind), .enumdef = &k_kind,
     .meta = "KIND", .help = "linear, sine, power, smoothstep or table"},
    {.key = "a", .kind = HV_OPT_NUMBER, .lo = -1e300, .hi = 1e300, .offset = DOFF(a), .help = "linear: f = a d + b"},
    {.key = "b", .kind = HV_OPT_NUMBER, .lo = -1e300, .hi = 1e300, .offset = DOFF(b), .help = "linear"},
    {.key = "k", .kind = HV_OPT_NUMBER, .lo = -1e300, .hi = 1e300, .offset = DOFF(k),
     .help = "sine: f = amplitude sin(k d + phase) + offset (required)"},
    {.key = "amplitude", .kind = HV_OPT_NUMBER, .lo = -1e300, .hi = 1e300, .offset = DOFF(amplitude), .help = "sine"},
    {.key = "phase", .kind = HV_OPT_NUMBER, .lo = -1e300, .hi = 1e300, .offset = DOFF(phase), .help = "sine"},
    {.key = "offset", .kind = HV_OPT_NUMBER, .lo = -1e300, .hi = 1e300, .offset = DOFF(offset), .help = "sine"},
    {.key = "p", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e300, .flags = HV_OPT_LO_OPEN | HV_OPT_UNSET0, .offset = DOFF(p),
     .help = "power: f = (d/dg)^p (required)"},
};
#undef DOFF

static void dfn_init(void *opts)
{
    hv_dfn_options *o = opts;
    memset(o, 0, sizeof *o);
    o->a = o->amplitude = 1;
}

/* Which parameters each kind takes ('r': required, 'o': optional), in the order of k_dfn_opts[1..] */
static const char *const k_takes[] = {"oo.....", "..rooo.", "......r", ".......", "......."};

static hv_status dfn_finish(const hv_optargs *args)
{
    const hv_dfn_options *o = args->opts;
    const char *takes = k_takes[o->kind];
    for (int i = 1; i < (int)HV_COUNT(k_dfn_opts); ++i) {
        const char *key = k_dfn_opts[i].key;
        char t = takes[i - 1];
        if (t == '.' && hv_optargs_given(args, key))
            return hv_error_option(HV_ERR_INVALID, "f of kind %s takes no {%s}", k_kind_names[o->kind], key);
        if (t == 'r' && !hv_optargs_given(args, key))
            return hv_error_option(HV_ERR_INVALID, "f of kind %s needs {%s}", k_kind_names[o->kind], key);
    }
    return HV_OK;
}

static const hv_option_set k_dfn_set = {"f", k_dfn_opts, (int)HV_COUNT(k_dfn_opts), sizeof(hv_dfn_options), dfn_init,
                                        NULL, 0, dfn_finish, NULL, NULL, 0};

const hv_option_set *hv_dfn_option_set(void) { return &k_dfn_set; }

hv_status hv_dfn_from_options(const hv_dfn_options *o, hv_dfn **out)
{
    switch (o->kind) {
    case HV_DFN_LINEAR: return hv_dfn_linear(o->a, o->b, out);
    case HV_DFN_SINE: return hv_dfn_sine(o->k, o->amplitude, o->phase, o->offset, out);
    case HV_DFN_POWER: return hv_dfn_power(o->p, out);
    case HV_DFN_SMOOTHSTEP: return hv_dfn_smoothstep(out);
    default: {
        const char *kind = hv_enum_name(&k_kind, (int)o->kind);
        return hv_error_set(HV_ERR_INVALID, "f of kind %s is made from its points (hv_dfn_table)", kind ? kind : "?");
    }
    }
}
