/* src/material/ags.c - active grading sources (Wu 2.2.2, eq. 19-23): ranges d-, dg, d+ on a
 * reference feature's distance, a distribution function f tabulated once over [0, dg], and
 * start/end compositions Ms, Me: P = Ms + f(d - d-) (Me - Ms) in the gradient range, with the
 * constant ranges taking f's boundary values so P is continuous (eq. 14); dg = 0 is a step (an
 * MMO). Also Wu's 3-material distance-field paradigm (eq. 13) as a constructor. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "material_internal.h"

/* d- may be below 0 only where d is: a signed feature (a half-space, a field of data that changes
 * sign); a distance is never negative, so there d- < 0 would be a mistake. */
static hv_status check_ranges(const hv_frf *frf, double dn, double dg, double dp)
{
    const char *names[3] = {"d- (negative constant range)", "dg (gradient range)",
                            "d+ (positive constant range)"};
    double v[3] = {dn, dg, dp};
    for (int i = 0; i < 3; ++i) {
        if (!isfinite(v[i])) return hv_error_set(HV_ERR_INVALID, "%s must be finite (got %g)", names[i], v[i]);
        if (v[i] >= 0 || (i == 0 && frf && hv_frf_is_signed(frf))) continue;
        if (i == 0)
            return hv_error_set(HV_ERR_INVALID,
                                "%s must be >= 0 for a %s feature, whose distances are never negative (got %g; a "
                                "signed feature, halfspace or field, takes d- < 0)",
                                names[i], frf ? hv_frf_kind_name(hv_frf_get_kind(frf)) : "distance", v[i]);
        return hv_error_set(HV_ERR_INVALID, "%s must be >= 0 (got %g)", names[i], v[i]);
    }
    return HV_OK;
}

/* Sample f into the table; f must stay in [lo, hi] (within 1e-9). */
static hv_status tabulate(hv_ags *a, const hv_dfn *f, double lo, double hi)
{
    double dg = a->d_grad, worst = 0, worst_d = 0, worst_f = 0;
    for (int i = 0; i <= HV_AGS_TABLE; ++i) {
        double d = dg * i / HV_AGS_TABLE;
        double v = hv_dfn_eval(f, d, dg);
        if (!isfinite(v))
            return hv_error_set(HV_ERR_INVALID, "f = %s is not a number at d = %.6g", hv_dfn_describe(f), d);
        double out = v < lo ? lo - v : v > hi ? v - hi : 0;
        if (out > worst) {
            worst = out;
            worst_d = d;
            worst_f = v;
        }
        a->table[i] = (float)HV_CLAMP(v, 0.0, 1.0);
    }
    if (worst > 1e-9)
        return hv_error_set(HV_ERR_INVALID,
                            "f = %s leaves [%g, %g] on the gradient range [0, %g]: f(%.6g) = %.9g",
                            hv_dfn_describe(f), lo, hi, dg, worst_d, worst_f);
    return HV_OK;
}

/* The property at f: Ps + f (Pe - Ps), or Ps (Pe/Ps)^f (logarithmic). */
static double target_value(const hv_ags *a, double f)
{
    if (a->log) return f <= 0 ? a->ps : f >= 1 ? a->pe : a->ps * pow(a->pe / a->ps, f);
    return a->ps + f * (a->pe - a->ps);
}

/* Check property targets against the source's table (the caller has checked f and dg). */
static hv_status check_target(const hv_calibration *c, const hv_property_target *t)
{
    const char *prop = hv_calibration_property(c), *unit = hv_calibration_unit(c);
    if (!t->property || strcmp(t->property, prop) != 0)
        return hv_error_set(HV_ERR_INVALID, "property targets for '%s', but the calibration table is for '%s'",
                            t->property ? t->property : "(none)", prop);
    double lo, hi;
    hv_calibration_range(c, &lo, &hi);
    const char *names[2] = {"Ps", "Pe"};
    double v[2] = {t->ps, t->pe};
    for (int i = 0; i < 2; ++i) {
        if (!isfinite(v[i])) return hv_error_set(HV_ERR_INVALID, "%s must be a finite number (got %g)", names[i], v[i]);
        if (!(v[i] >= lo && v[i] <= hi))
            return hv_error_set(HV_ERR_INVALID, "%s = %.9g%s%s is outside the calibration table's %s range [%.9g, %.9g]%s%s",
                                names[i], v[i], *unit ? " " : "", unit, prop, lo, hi, *unit ? " " : "", unit);
        if (t->log && !(v[i] > 0))
            return hv_error_set(HV_ERR_INVALID, "logarithmic property grading needs Ps, Pe > 0 (%s = %.9g)", names[i], v[i]);
    }
    return HV_OK;
}

/* Sample the property targets into the table: t(d) = table^-1(P(f(d))), f in [0, 1]. */
static hv_status tabulate_target(hv_ags *a, const hv_dfn *f)
{
    hv_status s = tabulate(a, f, 0.0, 1.0); /* f itself must stay in [0, 1]: P between Ps and Pe */
    if (s != HV_OK) return s;
    double dg = a->d_grad;
    for (int i = 0; i <= HV_AGS_TABLE; ++i) {
        double v = HV_CLAMP(hv_dfn_eval(f, dg * i / HV_AGS_TABLE, dg), 0.0, 1.0), t;
        if ((s = hv_calibration_invert(a->calib, target_value(a, v), &t)) != HV_OK) return s;
        a->table[i] = (float)HV_CLAMP(t, 0.0, 1.0);
    }
    return HV_OK;
}

hv_status hv_ags_create(const hv_ags_desc *desc, hv_ags **out)
{
    return hv_ags_create_calibrated(desc, NULL, NULL, out);
}

hv_status hv_ags_create_calibrated(const hv_ags_desc *desc, hv_calibration *calibration,
                                   const hv_property_target *target, hv_ags **out)
{
    *out = NULL;
    if (!desc->frf) return hv_error_set(HV_ERR_INVALID, "grading source without a reference feature");
    if (desc->m < 1 || desc->m > HV_MAX_MATERIALS)
        return hv_error_set(HV_ERR_INVALID, "material count %d out of range [1, %d]", desc->m, HV_MAX_MATERIALS);
    hv_status s = check_ranges(desc->frf, desc->d_neg, desc->d_grad, desc->d_pos);
    if (s != HV_OK) return s;
    if ((s = hv_composition_check(desc->ms, desc->m, "Ms")) != HV_OK ||
        (s = hv_composition_check(desc->me, desc->m, "Me")) != HV_OK)
        return s;
    if (desc->d_grad > 0 && !desc->f)
        return hv_error_set(HV_ERR_INVALID, "a gradient range dg = %g needs a distribution function f",
                            desc->d_grad);
    if (target) {
        if (!calibration)
            return hv_error_set(HV_ERR_INVALID, "property targets need a calibration table");
        if (!(desc->d_grad > 0))
            return hv_error_set(HV_ERR_INVALID, "property targets need a gradient range dg > 0 (for a step, give the "
                                "two compositions as Ms and Me)");
        if ((s = check_target(calibration, target)) != HV_OK) return s;
    }
    hv_ags *a = hv_calloc(1, sizeof *a);
    if (!a) return HV_ERR_NOMEM;
    a->refs = 1;
    a->frf = hv_frf_retain(desc->frf);
    a->d_neg = desc->d_neg;
    a->d_grad = desc->d_grad;
    a->d_pos = desc->d_pos;
    a->m = desc->m;
    memcpy(a->ms, desc->ms, (size_t)desc->m * sizeof(double));
    memcpy(a->me, desc->me, (size_t)desc->m * sizeof(double));
    snprintf(a->name, sizeof a->name, "%s", desc->name ? desc->name : "");
    a->calib = hv_calibration_retain(calibration);
    if (target) {
        a->has_target = 1;
        a->ps = target->ps;
        a->pe = target->pe;
        a->log = target->log;
        const char *u = hv_calibration_unit(calibration);
        snprintf(a->fdesc, sizeof a->fdesc, "%s from %.9g to %.9g%s%s%s, f = %s", target->property, a->ps, a->pe,
                 *u ? " " : "", u, a->log ? " (log)" : "", hv_dfn_describe(desc->f));
        if ((s = tabulate_target(a, desc->f)) != HV_OK) {
            hv_ags_release(a);
            return s;
        }
    } else if (desc->d_grad > 0) {
        snprintf(a->fdesc, sizeof a->fdesc, "%s", hv_dfn_describe(desc->f));
        if ((s = tabulate(a, desc->f, 0.0, 1.0)) != HV_OK) {
            hv_ags_release(a);
            return s;
        }
    } else {
        snprintf(a->fdesc, sizeof a->fdesc, "step");
        a->table[0] = 0.0f; /* unused: the step is evaluated directly */
    }
    *out = a;
    return HV_OK;
}

hv_status hv_ags_moved(const hv_ags *a, double d_neg, hv_ags **out)
{
    *out = NULL;
    hv_status s = check_ranges(a->frf, d_neg, a->d_grad, a->d_pos);
    if (s != HV_OK) return s;
    hv_ags *b = hv_malloc(sizeof *b);
    if (!b) return HV_ERR_NOMEM;
    memcpy(b, a, sizeof *b);
    b->refs = 1;
    b->d_neg = d_neg;
    hv_frf_retain(b->frf);
    hv_calibration_retain(b->calib);
    *out = b;
    return HV_OK;
}

hv_ags *hv_ags_retain(hv_ags *a)
{
    if (a) __atomic_add_fetch(&a->refs, 1, __ATOMIC_RELAXED);
    return a;
}

void hv_ags_release(hv_ags *a)
{
    if (!a || __atomic_sub_fetch(&a->refs, 1, __ATOMIC_ACQ_REL) > 0) return;
    hv_frf_release(a->frf);
    hv_calibration_release(a->calib);
    free(a);
}

void hv_ags_eval(const hv_ags *a, double d, double *p)
{
    double w = hv_ags_weight(a, (float)d);
    for (int j = 0; j < a->m; ++j) p[j] = a->ms[j] + w * (a->me[j] - a->ms[j]);
}

int hv_ags_materials(const hv_ags *a) { return a->m; }
const hv_frf *hv_ags_frf(const hv_ags *a) { return a->frf; }
const char *hv_ags_name(const hv_ags *a) { return a->name; }

const hv_calibration *hv_ags_calibration(const hv_ags *a) { return a->calib; }

int hv_ags_target(const hv_ags *a, hv_property_target *t)
{
    if (!a->has_target || !a->calib) return 0;
    t->property = hv_calibration_property(a->calib);
    t->ps = a->ps;
    t->pe = a->pe;
    t->log = a->log;
    return 1;
}

int hv_segment_t(const double *ms, const double *me, int m, const double *p, double *t)
{
    double num = 0, den = 0;
    for (int j = 0; j < m; ++j) {
        double e = me[j] - ms[j];
        num += (p[j] - ms[j]) * e;
        den += e * e;
    }
    if (!(den > 0)) return 0;
    double u = num / den;
    if (!(u >= -1e-3 && u <= 1 + 1e-3)) return 0;
    for (int j = 0; j < m; ++j)
        if (fabs(p[j] - (ms[j] + u * (me[j] - ms[j]))) > 1e-3) return 0;
    *t = HV_CLAMP(u, 0.0, 1.0);
    return 1;
}

int hv_ags_segment_t(const hv_ags *a, const double *p, double *t) { return hv_segment_t(a->ms, a->me, a->m, p, t); }

void hv_ags_ranges(const hv_ags *a, double *dn, double *dg, double *dp)
{
    if (dn) *dn = a->d_neg;
    if (dg) *dg = a->d_grad;
    if (dp) *dp = a->d_pos;
}

/* Wu eq. 13, P = [f, 1 - f - C, C], is Ms + w (Me - Ms) with Ms = [0, 1 - C, C],
 * Me = [1 - C, 0, C] and w = f / (1 - C): the ordinary machinery evaluates it. */
typedef struct wu3_ctx {
    const hv_dfn *f;
    double C, dg;
} wu3_ctx;

static double wu3_weight(void *user, double d)
{
    const wu3_ctx *c = user;
    double v = hv_dfn_eval(c->f, d, c->dg);
    return c->C < 1 ? v / (1 - c->C) : (v == 0 ? 0 : NAN);
}

hv_status hv_ags_wu3(hv_frf *frf, double d_neg, double d_grad, double d_pos, const hv_dfn *f, double C,
                     hv_ags **out)
{
    *out = NULL;
    if (!(C >= 0 && C <= 1))
        return hv_error_set(HV_ERR_INVALID, "Wu eq. 13: the constant composition C = %g must be in [0, 1]", C);
    if (!(d_grad > 0) || !f)
        return hv_error_set(HV_ERR_INVALID, "Wu eq. 13 needs a gradient range dg > 0 and f");
    hv_ags probe;
    memset(&probe, 0, sizeof probe);
    probe.d_grad = d_grad;
    hv_status s = tabulate(&probe, f, 0.0, 1.0 - C);
    if (s != HV_OK) return hv_error_prefix(s, "Wu eq. 13 (C = %g): ", C);
    wu3_ctx ctx = {f, C, d_grad};
    char desc[300];
    snprintf(desc, sizeof desc, "wu3(C=%g, f=%s)", C, hv_dfn_describe(f));
    hv_dfn *w;
    if ((s = hv_dfn_function(wu3_weight, &ctx, desc, &w)) != HV_OK) return s;
    double ms[3] = {0, 1 - C, C}, me[3] = {1 - C, 0, C};
    hv_ags_desc d = {frf, d_neg, d_grad, d_pos, w, ms, me, 3, "wu3"};
    s = hv_ags_create(&d, out);
    hv_dfn_destroy(w);
    return s;
}

json_t *hv_ags_to_doc(const hv_ags *a, int feature)
{
    json_t *j = json_pack("{s:o, s:i, s:o, s:o, s:o, s:o, s:o, s:o, s:o}", "name", hv_json_text(a->name), "feature",
                          feature, "feature_text", hv_json_text(hv_frf_describe(a->frf)), "d_neg",
                          hv_json_number(a->d_neg), "d_grad", hv_json_number(a->d_grad), "d_pos",
                          hv_json_number(a->d_pos), "f", hv_json_text(a->fdesc), "ms",
                          hv_json_numbers(a->ms, (size_t)a->m), "me", hv_json_numbers(a->me, (size_t)a->m));
    if (j && a->calib) { /* the calibration and targets: for profiles, and to rebuild the source */
        const hv_calibration *c = a->calib;
        int n = hv_calibration_rows(c);
        double *tv = hv_malloc_array((size_t)n, 2 * sizeof(double));
        json_t *cj = NULL;
        if (tv) {
            for (int i = 0; i < n; ++i) hv_calibration_row(c, i, &tv[i], &tv[n + i]);
            cj = json_pack("{s:o, s:o, s:o, s:o}", "property", hv_json_text(hv_calibration_property(c)), "unit",
                           hv_json_text(hv_calibration_unit(c)), "t", hv_json_numbers(tv, (size_t)n), "values",
                           hv_json_numbers(tv + n, (size_t)n));
            free(tv);
        }
        json_t *tj = a->has_target ? json_pack("{s:o, s:o, s:o, s:b}", "property",
                                               hv_json_text(hv_calibration_property(c)), "ps", hv_json_number(a->ps),
                                               "pe", hv_json_number(a->pe), "log", a->log)
                                   : NULL;
        int failed = !cj || hv_json_set(j, "calibration", cj) != 0;
        if (!failed && a->has_target) failed = !tj || hv_json_set(j, "target", tj) != 0;
        else json_decref(tj);
        if (failed) {
            json_decref(j);
            return NULL;
        }
    }
    if (j && a->d_grad > 0) { /* the tabulated f: what evaluation uses, so a reload is exact */
        json_t *t = json_array();
        int failed = !t;
        for (int i = 0; i <= HV_AGS_TABLE && !failed; ++i) failed = json_array_append_new(t, hv_json_float(a->table[i])) != 0;
        if (failed) json_decref(t);
        if (failed || hv_json_set(j, "table", t) != 0) {
            json_decref(j);
            return NULL;
        }
    }
    return j;
}

/* A calibration table of the object document: {"property", "unit", "t": [...], "values": [...]}. */
static hv_status calibration_from_doc(const json_t *cj, const char *what, hv_calibration **out)
{
    char w[300];
    snprintf(w, sizeof w, "%s: calibration", what);
    const char *prop, *unit = "";
    const json_t *tj, *vj;
    hv_status s = hv_json_get_string(cj, "property", w, &prop);
    if (s == HV_OK && json_object_get(cj, "unit")) s = hv_json_get_string(cj, "unit", w, &unit);
    if (s == HV_OK) s = hv_json_need(cj, "t", JSON_ARRAY, w, &tj);
    if (s == HV_OK) s = hv_json_need(cj, "values", JSON_ARRAY, w, &vj);
    if (s != HV_OK) return s;
    size_t n = json_array_size(tj);
    if (n != json_array_size(vj) || n < 2 || n > 100000)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: t and values must hold as many numbers, 2 to 100000 (%zu and %zu)", w,
                            n, json_array_size(vj));
    double *tv = hv_malloc_array(n, 2 * sizeof(double));
    if (!tv) return HV_ERR_NOMEM;
    s = hv_json_get_numbers(cj, "t", w, tv, n);
    if (s == HV_OK) s = hv_json_get_numbers(cj, "values", w, tv + n, n);
    if (s == HV_OK && (s = hv_calibration_create(prop, unit, tv, tv + n, (int)n, out)) != HV_OK)
        s = hv_error_prefix(HV_ERR_BAD_INPUT, "%s: ", w);
    free(tv);
    return s;
}

hv_status hv_ags_doc_calibration(const json_t *j, int m, const char *what, hv_calibration **calib, double *ms,
                                 double *me)
{
    *calib = NULL;
    const json_t *cj = json_object_get(j, "calibration");
    if (!cj) return HV_OK;
    hv_status s = hv_json_get_numbers(j, "ms", what, ms, (size_t)m);
    if (s == HV_OK) s = hv_json_get_numbers(j, "me", what, me, (size_t)m);
    if (s == HV_OK) s = calibration_from_doc(cj, what, calib);
    return s;
}

hv_status hv_ags_from_doc(const json_t *j, hv_frf *const *feats, size_t nf, int m, const char *what, hv_ags **out)
{
    *out = NULL;
    long long fi;
    double r[3], ms[HV_MAX_MATERIALS], me[HV_MAX_MATERIALS];
    const char *fdesc = "", *name = NULL;
    static const char *const ranges[3] = {"d_neg", "d_grad", "d_pos"};
    hv_status s = hv_json_get_int(j, "feature", what, 0, (long long)nf - 1, &fi);
    for (int q = 0; q < 3 && s == HV_OK; ++q) s = hv_json_get_number(j, ranges[q], what, &r[q]);
    if (s == HV_OK) s = hv_json_get_numbers(j, "ms", what, ms, (size_t)m);
    if (s == HV_OK) s = hv_json_get_numbers(j, "me", what, me, (size_t)m);
    if (s == HV_OK && json_object_get(j, "f")) s = hv_json_get_string(j, "f", what, &fdesc);
    if (s == HV_OK && json_object_get(j, "name")) s = hv_json_get_string(j, "name", what, &name);
    if (s != HV_OK) return s;
    float table[HV_AGS_TABLE + 1];
    if (r[1] > 0) {
        const json_t *t;
        if ((s = hv_json_need(j, "table", JSON_ARRAY, what, &t)) != HV_OK) return s;
        if (json_array_size(t) != HV_AGS_TABLE + 1)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: table has %zu values, not %d", what, json_array_size(t),
                                HV_AGS_TABLE + 1);
        for (size_t i = 0; i <= HV_AGS_TABLE; ++i) {
            const json_t *x = json_array_get(t, i);
            table[i] = json_is_number(x) ? (float)json_number_value(x) : NAN; /* refused below */
        }
    }
    hv_calibration *calib = NULL;
    const json_t *cj = json_object_get(j, "calibration"), *tj = json_object_get(j, "target");
    if (cj && (s = calibration_from_doc(cj, what, &calib)) != HV_OK) return s;
    s = hv_ags_from_parts(feats[fi], r[0], r[1], r[2], table, fdesc, ms, me, m, name, out);
    if (s == HV_OK && calib) (*out)->calib = hv_calibration_retain(calib);
    if (s == HV_OK && tj) {
        char w[300];
        snprintf(w, sizeof w, "%s: target", what);
        double t[2] = {0, 0};
        const char *prop = NULL;
        s = !calib ? hv_error_set(HV_ERR_BAD_INPUT, "%s: property targets without a calibration table", what) : HV_OK;
        if (s == HV_OK) s = hv_json_get_string(tj, "property", w, &prop);
        if (s == HV_OK) s = hv_json_get_number(tj, "ps", w, &t[0]);
        if (s == HV_OK) s = hv_json_get_number(tj, "pe", w, &t[1]);
        const json_t *lg = s == HV_OK ? json_object_get(tj, "log") : NULL;
        if (s == HV_OK && lg && !json_is_boolean(lg))
            s = hv_error_set(HV_ERR_BAD_INPUT, "%s: member 'log' must be true or false", w);
        hv_property_target pt = {prop, t[0], t[1], lg && json_is_true(lg)};
        if (s == HV_OK && (s = check_target(calib, &pt)) != HV_OK) s = hv_error_prefix(HV_ERR_BAD_INPUT, "%s: ", w);
        if (s == HV_OK) {
            (*out)->has_target = 1;
            (*out)->ps = pt.ps;
            (*out)->pe = pt.pe;
            (*out)->log = pt.log;
        }
        if (s != HV_OK) {
            hv_ags_release(*out);
            *out = NULL;
        }
    }
    hv_calibration_release(calib);
    return s == HV_OK ? s : hv_error_prefix(s == HV_ERR_INVALID ? HV_ERR_BAD_INPUT : s, "%s: ", what);
}

hv_status hv_ags_from_parts(hv_frf *frf, double d_neg, double d_grad, double d_pos, const float *table,
                            const char *fdesc, const double *ms, const double *me, int m,
                            const char *name, hv_ags **out)
{
    *out = NULL;
    hv_ags_desc d = {frf, d_neg, 0, d_pos, NULL, ms, me, m, name};
    hv_status s = hv_ags_create(&d, out);
    if (s != HV_OK) return s;
    hv_ags *a = *out;
    if (!(d_grad >= 0) || !isfinite(d_grad)) {
        hv_ags_release(a);
        *out = NULL;
        return hv_error_set(HV_ERR_INVALID, "dg must be >= 0 (got %g)", d_grad);
    }
    a->d_grad = d_grad;
    if (d_grad > 0) {
        for (int i = 0; i <= HV_AGS_TABLE; ++i) {
            if (!(table[i] >= 0.0f && table[i] <= 1.0f)) {
                hv_ags_release(a);
                *out = NULL;
                return hv_error_set(HV_ERR_INVALID, "stored f table: entry %d is %g, not in [0, 1]", i, (double)table[i]);
            }
            a->table[i] = table[i];
        }
    }
    snprintf(a->fdesc, sizeof a->fdesc, "%s", fdesc ? fdesc : "");
    return HV_OK;
}
