/* src/core/options.c - option domains (hovox/options.h): parsing values from text or numbers,
 * domain checks, rules between options, and the messages that name them. The one place where
 * an option's syntax and range are decided. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/options.h"

/* ---- enums --------------------------------------------------------------------------------- */

static int enum_value(const hv_enum_def *e, int i) { return e->values ? e->values[i] : i; }

const char *hv_enum_list(const hv_enum_def *e, char *buf, size_t size)
{
    size_t n = 0, count = 0;
    while (e->names[count]) ++count;
    if (size) buf[0] = '\0';
    for (size_t i = 0; i < count && n < size; ++i) {
        const char *sep = i == 0 ? "" : i + 1 == count ? " or " : ", ";
        int w = snprintf(buf + n, size - n, "%s%s", sep, e->names[i]);
        if (w < 0) break;
        n += (size_t)w;
    }
    return buf;
}

hv_status hv_enum_parse(const hv_enum_def *e, const char *name, int *out)
{
    for (int i = 0; e->names[i]; ++i)
        if (strcmp(e->names[i], name) == 0) {
            *out = enum_value(e, i);
            return HV_OK;
        }
    for (int i = 0; e->aliases && e->aliases[i]; i += 2)
        if (strcmp(e->aliases[i], name) == 0) return hv_enum_parse(e, e->aliases[i + 1], out);
    char list[512];
    return hv_error_set(HV_ERR_INVALID, "%s must be %s, got '%s'", e->what,
                        hv_enum_list(e, list, sizeof list), name);
}

const char *hv_enum_name(const hv_enum_def *e, int value)
{
    for (int i = 0; e->names[i]; ++i)
        if (enum_value(e, i) == value) return e->names[i];
    return NULL;
}

/* ---- colours ------------------------------------------------------------------------------- */

hv_status hv_color_parse(const char *s, float rgba[4])
{
    rgba[3] = 1.0f;
    if (s[0] == '#') {
        size_t n = strlen(s + 1);
        if (n != 6 && n != 8) goto bad;
        for (size_t i = 0; i < n; ++i)
            if (!isxdigit((unsigned char)s[1 + i])) goto bad;
        unsigned long v = strtoul(s + 1, NULL, 16);
        if (n == 8) {
            rgba[3] = (float)(v & 0xFF) / 255.0f;
            v >>= 8;
        }
        rgba[0] = (float)((v >> 16) & 0xFF) / 255.0f;
        rgba[1] = (float)((v >> 8) & 0xFF) / 255.0f;
        rgba[2] = (float)(v & 0xFF) / 255.0f;
        return HV_OK;
    }
    {
        double v[4] = {0, 0, 0, 1};
        const char *p = s;
        int k = 0;
        for (; k < 4; ++k) {
            char *end;
            v[k] = strtod(p, &end);
            if (end == p || !(v[k] >= 0 && v[k] <= 1)) goto bad;
            p = end;
            if (*p == '\0') break;
            if (*p != ',') goto bad;
            ++p;
        }
        if (k < 2 || *p != '\0') goto bad;
        for (int i = 0; i < 4; ++i) rgba[i] = (float)v[i];
        return HV_OK;
    }
bad:
    return hv_error_set(HV_ERR_INVALID,
                        "colour '%s' is not #rrggbb, #rrggbbaa or r,g,b[,a] with values in [0,1]", s);
}

/* ---- numbers ------------------------------------------------------------------------------- */

static int count_of(const hv_option *o) { return o->count > 0 ? o->count : 1; }

static int elem_integral(hv_opt_elem e) { return e != HV_ELEM_DOUBLE && e != HV_ELEM_FLOAT; }

static void elem_limits(hv_opt_elem e, double *lo, double *hi)
{
    switch (e) {
    case HV_ELEM_INT: *lo = -2147483648.0; *hi = 2147483647.0; break;
    case HV_ELEM_INT64: *lo = -9.2e18; *hi = 9.2e18; break;
    case HV_ELEM_UINT64: *lo = 0; *hi = 18446744073709551616.0; break;
    case HV_ELEM_UINT8: *lo = 0; *hi = 255; break;
    case HV_ELEM_FLOAT: *lo = -3.4e38; *hi = 3.4e38; break;
    default: *lo = -HUGE_VAL; *hi = HUGE_VAL; break;
    }
}

static void *field(const hv_option *o, void *opts) { return (char *)opts + o->offset; }
static const void *cfield(const hv_option *o, const void *opts) { return (const char *)opts + o->offset; }

static double get_elem(const hv_option *o, const void *opts, int i)
{
    const void *p = cfield(o, opts);
    switch (o->elem) {
    case HV_ELEM_FLOAT: return ((const float *)p)[i];
    case HV_ELEM_INT: return ((const int *)p)[i];
    case HV_ELEM_INT64: return (double)((const int64_t *)p)[i];
    case HV_ELEM_UINT64: return (double)((const uint64_t *)p)[i];
    case HV_ELEM_UINT8: return ((const uint8_t *)p)[i];
    default: return ((const double *)p)[i];
    }
}

static void put_elem(const hv_option *o, void *opts, int i, double v)
{
    void *p = field(o, opts);
    switch (o->elem) {
    case HV_ELEM_FLOAT: ((float *)p)[i] = (float)v; break;
    case HV_ELEM_INT: ((int *)p)[i] = (int)v; break;
    case HV_ELEM_INT64: ((int64_t *)p)[i] = (int64_t)v; break;
    case HV_ELEM_UINT64: ((uint64_t *)p)[i] = (uint64_t)v; break;
    case HV_ELEM_UINT8: ((uint8_t *)p)[i] = (uint8_t)v; break;
    default: ((double *)p)[i] = v; break;
    }
}

static const char *unit_text(const hv_option *o, char *buf, size_t size)
{
    if (o->unit && *o->unit) snprintf(buf, size, " %s", o->unit);
    else if (size) buf[0] = '\0';
    return buf;
}

/* "in (0, 4] voxels", "> 0 mm", ">= 0", "an integer in [1, 8]" */
static const char *domain_text(const hv_option *o, char *buf, size_t size)
{
    double lo = o->lo, hi = o->hi, tlo, thi;
    elem_limits(o->elem, &tlo, &thi);
    if (lo == 0 && hi == 0) {
        lo = tlo;
        hi = thi;
    }
    char u[64];
    unit_text(o, u, sizeof u);
    if (o->flags & HV_OPT_ZERO_OK) {
        hv_option plain = *o;
        plain.flags &= ~HV_OPT_ZERO_OK;
        char d[160];
        snprintf(buf, size, "0 (automatic) or %s", domain_text(&plain, d, sizeof d));
        return buf;
    }
    /* what: "an integer ", "" (a number), "2 integers ", "3 numbers " */
    char integer[48];
    int n = count_of(o);
    if (n > 1 && (o->flags & (HV_OPT_SCALAR | HV_OPT_FIRST))) snprintf(integer, sizeof integer, "%s", elem_integral(o->elem) ? "integers " : "");
    else if (n > 1) snprintf(integer, sizeof integer, "%d %s ", n, elem_integral(o->elem) ? "integers" : "numbers");
    else snprintf(integer, sizeof integer, "%s", elem_integral(o->elem) ? "an integer " : "");
    int has_lo = lo > tlo || (lo == tlo && isfinite(lo) && (o->flags & HV_OPT_LO_OPEN));
    int has_hi = hi < thi && isfinite(hi);
    if (has_lo && has_hi)
        snprintf(buf, size, "%sin %c%.10g, %.10g%c%s", integer, (o->flags & HV_OPT_LO_OPEN) ? '(' : '[', lo, hi,
                 (o->flags & HV_OPT_HI_OPEN) ? ')' : ']', u);
    else if (has_lo)
        snprintf(buf, size, "%s%s %.10g%s", integer, (o->flags & HV_OPT_LO_OPEN) ? ">" : ">=", lo, u);
    else if (has_hi)
        snprintf(buf, size, "%s%s %.10g%s", integer, (o->flags & HV_OPT_HI_OPEN) ? "<" : "<=", hi, u);
    else if (n > 1)
        snprintf(buf, size, "%d finite numbers", n);
    else
        snprintf(buf, size, "%s", elem_integral(o->elem) ? "an integer" : "a finite number");
    return buf;
}

static int in_domain(const hv_option *o, double v)
{
    double lo = o->lo, hi = o->hi, tlo, thi;
    elem_limits(o->elem, &tlo, &thi);
    if (lo == 0 && hi == 0) {
        lo = tlo;
        hi = thi;
    }
    if (!isfinite(v)) return 0;
    if (v == 0 && (o->flags & HV_OPT_ZERO_OK)) return 1;
    if (elem_integral(o->elem) && (v != floor(v) || v < tlo || v > thi)) return 0;
    if ((o->flags & HV_OPT_LO_OPEN) ? !(v > lo) : !(v >= lo)) return 0;
    if ((o->flags & HV_OPT_HI_OPEN) ? !(v < hi) : !(v <= hi)) return 0;
    return 1;
}

/* The value as the user gave it, for messages: 'text' or numbers. */
static const char *value_text(const hv_opt_value *v, char *buf, size_t size)
{
    if (v->type == HV_VALUE_TEXT) {
        snprintf(buf, size, "'%s'", v->text ? v->text : "");
    } else if (v->type == HV_VALUE_BOOL) {
        snprintf(buf, size, "%s", v->boolean ? "true" : "false");
    } else {
        size_t n = 0;
        if (size) buf[0] = '\0';
        if (v->n > 1 && n < size) n += (size_t)snprintf(buf + n, size - n, "{");
        for (int i = 0; i < v->n && n < size; ++i)
            n += (size_t)snprintf(buf + n, size - n, "%s%.10g", i ? ", " : "", v->numbers[i]);
        if (v->n > 1 && n < size) snprintf(buf + n, size - n, "}");
        if (v->n == 0) snprintf(buf, size, "{}");
    }
    return buf;
}

static hv_status out_of_domain(const hv_option *o, const hv_opt_value *v)
{
    char d[160], t[256];
    if (v->type == HV_VALUE_TEXT) snprintf(t, sizeof t, "%s", v->text); /* numbers: no quotes */
    else value_text(v, t, sizeof t);
    return hv_error_option(HV_ERR_INVALID, "{%s} must be %s, got %s", o->key, domain_text(o, d, sizeof d), t);
}

static hv_status not_numbers(const hv_option *o, const hv_opt_value *v)
{
    char t[256];
    int n = count_of(o);
    const char *kind = elem_integral(o->elem) ? "integer" : "number";
    if (n == 1)
        return hv_error_option(HV_ERR_INVALID, "{%s} must be a%s %s, got %s", o->key,
                               elem_integral(o->elem) ? "n" : "", kind, value_text(v, t, sizeof t));
    if (o->flags & (HV_OPT_SCALAR | HV_OPT_FIRST))
        return hv_error_option(HV_ERR_INVALID, "{%s} must be one %s or %d (%s), got %s", o->key, kind, n,
                               o->meta ? o->meta : "comma-separated", value_text(v, t, sizeof t));
    return hv_error_option(HV_ERR_INVALID, "{%s} must be %d %ss (%s), got %s", o->key, n, kind,
                           o->meta ? o->meta : "comma-separated", value_text(v, t, sizeof t));
}

/* A decimal number: digits, sign, point and exponent only (strtod alone would also take hex,
 * "inf" and "nan"). Returns the end, or NULL. */
static const char *scan_number(const char *p, int integer_only, double *out, uint64_t *u64)
{
    const char *q = p;
    while (*q && strchr(integer_only ? "0123456789+-" : "0123456789+-.eE", *q)) ++q;
    if (q == p || q - p > 63) return NULL;
    char buf[64];
    memcpy(buf, p, (size_t)(q - p));
    buf[q - p] = '\0';
    char *end;
    errno = 0;
    if (u64) {
        if (buf[0] == '-' || buf[0] == '+') return NULL;
        *u64 = strtoull(buf, &end, 10);
        *out = (double)*u64;
    } else {
        *out = strtod(buf, &end);
    }
    if (*end != '\0' || errno == ERANGE) return NULL;
    return q;
}

/* Numbers from text: "a,b,c" (or "WxH" with HV_OPT_XSEP). Returns the count, -1 when not
 * numbers. A lone 64-bit unsigned integer is read exactly (*u64) so seeds survive. */
static int parse_numbers(const hv_option *o, const char *s, double *out, int max, uint64_t *u64)
{
    const char *p = s;
    int n = 0;
    char sep = ',';
    if ((o->flags & HV_OPT_XSEP) && !strchr(s, ',') && (strchr(s, 'x') || strchr(s, 'X'))) sep = 'x';
    int exact = o->elem == HV_ELEM_UINT64 && max == 1;
    while (1) {
        if (n == max) return -1;
        while (*p == ' ') ++p;
        const char *end = scan_number(p, exact, &out[n], exact ? u64 : NULL);
        if (!end) return -1;
        ++n;
        p = end;
        while (*p == ' ') ++p;
        if (*p == '\0') return n;
        if (*p == sep || (sep == 'x' && *p == 'X')) ++p;
        else return -1;
    }
}

static hv_status set_numbers(const hv_option *o, void *opts, const hv_opt_value *v)
{
    int want = count_of(o), n = 0;
    double num[64];
    uint64_t u64 = 0;
    int exact64 = 0;
    if (v->type == HV_VALUE_TEXT) {
        n = parse_numbers(o, v->text, num, want > 64 ? 64 : want, &u64);
        exact64 = o->elem == HV_ELEM_UINT64 && want == 1 && n == 1;
        if (n < 0) return not_numbers(o, v);
    } else if (v->type == HV_VALUE_NUMBERS) {
        n = v->n;
        if (n > want || n > 64) return not_numbers(o, v);
        for (int i = 0; i < n; ++i) num[i] = v->numbers[i];
    } else {
        return not_numbers(o, v);
    }
    int scalar = n == 1 && want > 1 && (o->flags & (HV_OPT_SCALAR | HV_OPT_FIRST));
    if (n != want && !scalar) return not_numbers(o, v);
    for (int i = 0; i < n; ++i)
        if (!in_domain(o, num[i])) return out_of_domain(o, v);
    if (exact64) {
        *(uint64_t *)field(o, opts) = u64;
        return HV_OK;
    }
    if (scalar) {
        for (int i = 0; i < want; ++i) put_elem(o, opts, i, (o->flags & HV_OPT_SCALAR) || i == 0 ? num[0] : 0);
        return HV_OK;
    }
    for (int i = 0; i < n; ++i) put_elem(o, opts, i, num[i]);
    return HV_OK;
}

/* ---- other kinds ----------------------------------------------------------------------------- */

static hv_status set_bytes(const hv_option *o, void *opts, const hv_opt_value *v)
{
    double b = -1;
    if (v->type == HV_VALUE_NUMBERS && v->n == 1) {
        b = v->numbers[0];
    } else if (v->type == HV_VALUE_TEXT) {
        char *end;
        errno = 0;
        double x = strtod(v->text, &end);
        if (end != v->text && errno != ERANGE && x >= 0) {
            double mul = 1;
            switch (*end) {
            case 'k': case 'K': mul = 1024.0; ++end; break;
            case 'm': case 'M': mul = 1048576.0; ++end; break;
            case 'g': case 'G': mul = 1073741824.0; ++end; break;
            case 't': case 'T': mul = 1099511627776.0; ++end; break;
            default: break;
            }
            if (*end == 'B' || *end == 'b') ++end;
            if (*end == '\0') b = x * mul;
        }
    }
    char t[256];
    if (!(b >= 0 && b < 1.8e19))
        return hv_error_option(HV_ERR_INVALID, "{%s} must be a size such as 512M or 8G, got %s", o->key,
                               value_text(v, t, sizeof t));
    if (!in_domain(o, b)) {
        char d[160];
        return hv_error_option(HV_ERR_INVALID, "{%s} must be %s bytes, got %s", o->key,
                               domain_text(o, d, sizeof d), value_text(v, t, sizeof t));
    }
    *(uint64_t *)field(o, opts) = (uint64_t)b;
    return HV_OK;
}

static hv_status set_enum(const hv_option *o, void *opts, const hv_opt_value *v)
{
    char t[256], list[512];
    int x;
    if (v->type != HV_VALUE_TEXT || hv_enum_parse(o->enumdef, v->text, &x) != HV_OK)
        return hv_error_option(HV_ERR_INVALID, "{%s} must be %s, got %s", o->key,
                               hv_enum_list(o->enumdef, list, sizeof list), value_text(v, t, sizeof t));
    *(int *)field(o, opts) = x;
    return HV_OK;
}

static hv_status set_color(const hv_option *o, void *opts, const hv_opt_value *v)
{
    float c[4] = {0, 0, 0, 1};
    int ok = 0, alpha = (o->flags & HV_OPT_ALPHA) != 0;
    if (v->type == HV_VALUE_TEXT) {
        if (alpha && (strcmp(v->text, "transparent") == 0 || strcmp(v->text, "none") == 0)) {
            c[3] = 0;
            ok = 1;
        } else {
            ok = hv_color_parse(v->text, c) == HV_OK;
        }
    } else if (v->type == HV_VALUE_NUMBERS && v->n >= 3 && v->n <= 4) {
        ok = 1;
        for (int i = 0; i < v->n; ++i) {
            if (!(v->numbers[i] >= 0 && v->numbers[i] <= 1)) ok = 0;
            c[i] = (float)v->numbers[i];
        }
    }
    if (ok && !alpha && c[3] != 1.0f) ok = 0;
    char t[256];
    if (!ok)
        return hv_error_option(HV_ERR_INVALID, "{%s} must be a colour (%s), got %s", o->key,
                               alpha ? "#rrggbb, #rrggbbaa, r,g,b[,a] in 0..1 or transparent"
                                     : "#rrggbb or r,g,b in 0..1",
                               value_text(v, t, sizeof t));
    if (o->elem == HV_ELEM_UINT8) {
        uint8_t *p = field(o, opts);
        for (int k = 0; k < 3; ++k) p[k] = (uint8_t)(c[k] * 255.0f + 0.5f);
    } else {
        memcpy(field(o, opts), c, sizeof c);
    }
    return HV_OK;
}

static hv_status set_range(const hv_option *o, void *opts, const hv_opt_value *v)
{
    size_t a = 0, b = 0;
    int ok = 0;
    if (v->type == HV_VALUE_TEXT) {
        const char *s = v->text, *colon = strchr(s, ':');
        ok = colon != NULL;
        char *end;
        if (ok && colon != s) {
            unsigned long long x = strtoull(s, &end, 10);
            ok = end == colon && isdigit((unsigned char)*s);
            a = (size_t)x;
        }
        if (ok && colon[1]) {
            unsigned long long x = strtoull(colon + 1, &end, 10);
            ok = *end == '\0' && isdigit((unsigned char)colon[1]);
            b = (size_t)x;
            if (ok && b == 0) ok = 0;
        }
    } else if (v->type == HV_VALUE_NUMBERS && v->n == 2) {
        /* both ends below 2^64 before they become size_t (fuzzing found 1e111 for A) */
        ok = v->numbers[0] >= 0 && v->numbers[1] >= 0 && v->numbers[0] == floor(v->numbers[0]) &&
             v->numbers[1] == floor(v->numbers[1]) && v->numbers[0] < 1.8e19 && v->numbers[1] < 1.8e19;
        a = ok ? (size_t)v->numbers[0] : 0;
        b = ok ? (size_t)v->numbers[1] : 0;
    }
    if (ok && b && a >= b) ok = 0;
    char t[256];
    if (!ok)
        return hv_error_option(HV_ERR_INVALID,
                               "{%s} must be a range A:B with A < B (B excluded; A: or :B for the ends), got %s",
                               o->key, value_text(v, t, sizeof t));
    size_t *p = field(o, opts);
    p[0] = a;
    p[1] = b;
    return HV_OK;
}

hv_status hv_option_set_value(const hv_option *o, void *opts, const hv_opt_value *v)
{
    hv_status s;
    char t[256];
    switch (o->kind) {
    case HV_OPT_FLAG:
        if (v->type != HV_VALUE_BOOL)
            return hv_error_option(HV_ERR_INVALID, "{%s} must be true or false, got %s", o->key,
                                   value_text(v, t, sizeof t));
        if (o->parse) s = o->parse(o, opts, v); /* a flag routed elsewhere (a CLI group's member) */
        else {
            *(int *)field(o, opts) = v->boolean != 0;
            s = HV_OK;
        }
        break;
    case HV_OPT_NUMBER: s = set_numbers(o, opts, v); break;
    case HV_OPT_BYTES: s = set_bytes(o, opts, v); break;
    case HV_OPT_ENUM: s = set_enum(o, opts, v); break;
    case HV_OPT_STRING:
        if (v->type != HV_VALUE_TEXT)
            return hv_error_option(HV_ERR_INVALID, "{%s} must be a string, got %s", o->key,
                                   value_text(v, t, sizeof t));
        *(const char **)field(o, opts) = v->text;
        s = HV_OK;
        break;
    case HV_OPT_COLOR: s = set_color(o, opts, v); break;
    case HV_OPT_RANGE: s = set_range(o, opts, v); break;
    case HV_OPT_CUSTOM: s = o->parse(o, opts, v); break;
    default: s = hv_error_set(HV_ERR_INTERNAL, "option %s: unknown kind", o->key);
    }
    if (s == HV_OK && o->check) s = o->check(o, opts);
    return s;
}

hv_status hv_option_set_text(const hv_option *opt, void *opts, const char *text)
{
    hv_opt_value v = {HV_VALUE_TEXT, text, NULL, 0, 0};
    return hv_option_set_value(opt, opts, &v);
}

/* ---- checks of filled structs ---------------------------------------------------------------- */

hv_status hv_option_copy(const hv_option_set *set, const char *key, void *dst, const void *src)
{
    const hv_option *o = hv_option_find(set, key);
    if (!o) return hv_error_set(HV_ERR_NOT_FOUND, "%s: no option %s", set->name, key);
    size_t n;
    switch (o->kind) {
    case HV_OPT_NUMBER:
        for (int i = 0; i < count_of(o); ++i) put_elem(o, dst, i, get_elem(o, src, i));
        return HV_OK;
    case HV_OPT_FLAG:
    case HV_OPT_ENUM: n = sizeof(int); break;
    case HV_OPT_BYTES: n = sizeof(uint64_t); break;
    case HV_OPT_STRING: n = sizeof(const char *); break;
    case HV_OPT_RANGE: n = 2 * sizeof(size_t); break;
    default: return hv_error_set(HV_ERR_INVALID, "%s: option %s cannot be copied", set->name, key);
    }
    memcpy(field(o, dst), cfield(o, src), n);
    return HV_OK;
}

hv_status hv_option_check(const hv_option *o, const void *opts)
{
    if (o->kind == HV_OPT_NUMBER || o->kind == HV_OPT_BYTES) {
        int n = o->kind == HV_OPT_BYTES ? 1 : count_of(o);
        double num[64];
        int skip_rest = (o->flags & HV_OPT_FIRST) && n > 1;
        if ((n > 1 && (o->flags & (HV_OPT_FIRST | HV_OPT_SCALAR))) || (o->flags & HV_OPT_UNSET0)) { /* all zero: not set */
            int zero = 1;
            for (int i = 0; i < n; ++i) zero &= get_elem(o, opts, i) == 0;
            if (zero) return o->check ? o->check(o, opts) : HV_OK;
        }
        for (int i = 0; i < n && i < 64; ++i) {
            num[i] = o->kind == HV_OPT_BYTES ? (double)*(const uint64_t *)cfield(o, opts) : get_elem(o, opts, i);
            if (skip_rest && i > 0 && num[i] == 0) continue;
            if (!in_domain(o, num[i])) {
                hv_opt_value v = {HV_VALUE_NUMBERS, NULL, num, i + 1, 0};
                if (n > 1) {
                    v.numbers = num + i;
                    v.n = 1;
                }
                return out_of_domain(o, &v);
            }
        }
    } else if (o->kind == HV_OPT_ENUM) {
        int x = *(const int *)cfield(o, opts);
        if (!hv_enum_name(o->enumdef, x)) {
            char list[512];
            return hv_error_option(HV_ERR_INVALID, "{%s} must be %s, got the value %d", o->key,
                                   hv_enum_list(o->enumdef, list, sizeof list), x);
        }
    } else if (o->kind == HV_OPT_COLOR && o->elem == HV_ELEM_FLOAT) {
        const float *c = cfield(o, opts);
        for (int k = 0; k < 4; ++k)
            if (!(c[k] >= 0 && c[k] <= 1))
                return hv_error_option(HV_ERR_INVALID, "{%s} component %d must be in [0, 1], got %g", o->key, k,
                                       (double)c[k]);
    } else if (o->kind == HV_OPT_STRING) {
        return HV_OK; /* a text's own check (a known profile, an image extension) is about what
                         a person typed: it runs when the value is set, not on structs filled
                         in C, where a string may be any label */
    } else if (o->kind == HV_OPT_RANGE) {
        const size_t *p = cfield(o, opts);
        if (p[1] && p[0] >= p[1])
            return hv_error_option(HV_ERR_INVALID, "{%s} must be a range A:B with A < B, got %zu:%zu", o->key,
                                   p[0], p[1]);
    }
    if (o->check) return o->check(o, opts);
    return HV_OK;
}

hv_status hv_options_check(const hv_option_set *set, const void *opts)
{
    for (int i = 0; i < set->count; ++i) {
        hv_status s = hv_option_check(&set->options[i], opts);
        if (s != HV_OK) return s;
    }
    return set->validate ? set->validate(opts) : HV_OK;
}

const char *hv_option_format(const hv_option *o, const void *opts, char *buf, size_t size)
{
    if (!size) return buf;
    buf[0] = '\0';
    switch (o->kind) {
    case HV_OPT_FLAG: snprintf(buf, size, "%s", *(const int *)cfield(o, opts) ? "true" : "false"); break;
    case HV_OPT_NUMBER: {
        size_t n = 0;
        int c = count_of(o);
        if ((o->flags & HV_OPT_FIRST) && c > 1) {
            int rest = 0;
            for (int i = 1; i < c; ++i) rest |= get_elem(o, opts, i) != 0;
            if (!rest) c = 1;
        }
        if (o->elem == HV_ELEM_UINT64 && c == 1) {
            snprintf(buf, size, "%llu", (unsigned long long)*(const uint64_t *)cfield(o, opts));
            break;
        }
        for (int i = 0; i < c && n < size; ++i)
            n += (size_t)snprintf(buf + n, size - n, "%s%.10g", i ? "," : "", get_elem(o, opts, i));
        break;
    }
    case HV_OPT_BYTES: {
        uint64_t b = *(const uint64_t *)cfield(o, opts);
        const char *suffix = "KMGT";
        int k = -1;
        while (b && b % 1024 == 0 && k < 3) {
            b /= 1024;
            ++k;
        }
        if (k >= 0) snprintf(buf, size, "%llu%c", (unsigned long long)b, suffix[k]);
        else snprintf(buf, size, "%llu", (unsigned long long)b);
        break;
    }
    case HV_OPT_ENUM: {
        const char *name = hv_enum_name(o->enumdef, *(const int *)cfield(o, opts));
        snprintf(buf, size, "%s", name ? name : "?");
        break;
    }
    case HV_OPT_STRING: {
        const char *s = *(const char *const *)cfield(o, opts);
        snprintf(buf, size, "%s", s ? s : "");
        break;
    }
    case HV_OPT_COLOR: {
        float c[4] = {0, 0, 0, 1};
        if (o->elem == HV_ELEM_UINT8) {
            const uint8_t *p = cfield(o, opts);
            snprintf(buf, size, "#%02x%02x%02x", p[0], p[1], p[2]);
            break;
        }
        memcpy(c, cfield(o, opts), sizeof c);
        if (c[3] == 0) {
            snprintf(buf, size, "transparent");
            break;
        }
        unsigned v[4];
        for (int k = 0; k < 4; ++k) v[k] = (unsigned)lrintf(HV_CLAMP(c[k], 0.0f, 1.0f) * 255.0f);
        if (v[3] == 255) snprintf(buf, size, "#%02x%02x%02x", v[0], v[1], v[2]);
        else snprintf(buf, size, "#%02x%02x%02x%02x", v[0], v[1], v[2], v[3]);
        break;
    }
    case HV_OPT_RANGE: {
        const size_t *p = cfield(o, opts);
        if (p[1]) snprintf(buf, size, "%zu:%zu", p[0], p[1]);
        else snprintf(buf, size, "%zu:", p[0]);
        break;
    }
    default: break;
    }
    return buf;
}

const hv_option *hv_option_find(const hv_option_set *set, const char *key)
{
    for (int i = 0; i < set->count; ++i)
        if (strcmp(set->options[i].key, key) == 0) return &set->options[i];
    return NULL;
}

hv_status hv_option_known(const hv_option_set *set, const char *const *extra, const char *key)
{
    if (hv_option_find(set, key)) return HV_OK;
    for (int i = 0; i < set->alias_count; ++i)
        if (strcmp(set->aliases[i].name, key) == 0) return HV_OK;
    for (const char *const *q = extra; q && *q; ++q)
        if (strcmp(*q, key) == 0) return HV_OK;
    char list[1024];
    size_t n = 0;
    list[0] = '\0';
    for (int i = 0; i < set->count && n < sizeof list; ++i)
        n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", n ? ", " : "", set->options[i].key);
    for (int i = 0; i < set->alias_count && n < sizeof list; ++i)
        n += (size_t)snprintf(list + n, sizeof list - n, ", %s", set->aliases[i].name);
    for (const char *const *q = extra; q && *q && n < sizeof list; ++q)
        n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", n ? ", " : "", *q);
    return hv_error_set(HV_ERR_NOT_FOUND, "unknown option '%s' (options: %s)", key, list);
}

/* ---- collecting ------------------------------------------------------------------------------ */

void hv_optargs_begin(hv_optargs *args, const hv_option_set *set, void *opts)
{
    args->set = set;
    args->opts = opts;
    args->given = 0;
    if (set->init) set->init(opts);
    else memset(opts, 0, set->size);
}

static int index_of(const hv_option_set *set, const char *key)
{
    const hv_option *o = hv_option_find(set, key);
    return o ? (int)(o - set->options) : -1;
}

hv_status hv_optargs_set(hv_optargs *args, const char *key, const hv_opt_value *value)
{
    int i = index_of(args->set, key);
    for (int k = 0; i < 0 && k < args->set->alias_count; ++k) {
        const hv_opt_alias *a = &args->set->aliases[k];
        if (strcmp(a->name, key) != 0) continue;
        if (value->type != HV_VALUE_BOOL) {
            char t[256];
            return hv_error_option(HV_ERR_INVALID, "{%s} must be true or false (it stands for %s = %s), got %s",
                                   a->name, a->key, a->value, value_text(value, t, sizeof t));
        }
        if (!value->boolean) return HV_OK;
        hv_opt_value v = {HV_VALUE_TEXT, a->value, NULL, 0, 0};
        return hv_optargs_set(args, a->key, &v);
    }
    if (i < 0) {
        char list[1024];
        size_t n = 0;
        list[0] = '\0';
        for (int k = 0; k < args->set->count && n < sizeof list; ++k)
            n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", k ? ", " : "", args->set->options[k].key);
        for (int k = 0; k < args->set->alias_count && n < sizeof list; ++k)
            n += (size_t)snprintf(list + n, sizeof list - n, ", %s", args->set->aliases[k].name);
        return hv_error_set(HV_ERR_NOT_FOUND, "unknown option '%s' (options of %s: %s)", key, args->set->name, list);
    }
    const hv_option *o = &args->set->options[i];
    uint64_t bit = (uint64_t)1 << i;
    if ((args->given & bit) && !(o->flags & HV_OPT_REPEAT))
        return hv_error_option(HV_ERR_INVALID, "{%s} given twice", o->key);
    hv_status s = hv_option_set_value(o, args->opts, value);
    if (s == HV_OK) args->given |= bit;
    return s;
}

int hv_optargs_given(const hv_optargs *args, const char *key)
{
    int i = index_of(args->set, key);
    return i >= 0 && (args->given & ((uint64_t)1 << i)) != 0;
}

/* "a|b" holds the name of b's current value */
static int value_listed(const hv_optargs *args, const char *key, const char *values)
{
    const hv_option *o = hv_option_find(args->set, key);
    if (!o || o->kind != HV_OPT_ENUM) return 0;
    const char *name = hv_enum_name(o->enumdef, *(const int *)cfield(o, args->opts));
    if (!name) return 0;
    size_t n = strlen(name);
    for (const char *p = values; p && *p;) {
        const char *bar = strchr(p, '|');
        size_t len = bar ? (size_t)(bar - p) : strlen(p);
        if (len == n && strncmp(p, name, n) == 0) return 1;
        p = bar ? bar + 1 : NULL;
    }
    return 0;
}

static hv_status rule_failed(const hv_opt_rule *r)
{
    const char *sep = r->why ? ": " : "", *why = r->why ? r->why : "";
    switch (r->kind) {
    case HV_RULE_EXCLUDES:
        return hv_error_option(HV_ERR_INVALID, "{%s} and {%s} exclude each other%s%s", r->a, r->b, sep, why);
    case HV_RULE_NEEDS: return hv_error_option(HV_ERR_INVALID, "{%s} needs {%s}%s%s", r->a, r->b, sep, why);
    case HV_RULE_NEEDS_VALUE: {
        char v[128];
        size_t n = 0;
        for (const char *p = r->value; *p && n + 6 < sizeof v; ++p) {
            if (*p == '|') {
                memcpy(v + n, " or ", 4);
                n += 4;
            } else {
                v[n++] = *p;
            }
        }
        v[n] = '\0';
        return hv_error_option(HV_ERR_INVALID, "{%s} needs {%s} %s%s%s", r->a, r->b, v, sep, why);
    }
    }
    return HV_ERR_INTERNAL;
}

hv_status hv_optargs_finish(hv_optargs *args)
{
    const hv_option_set *set = args->set;
    for (int i = 0; i < set->count; ++i)
        if ((set->options[i].flags & HV_OPT_REQUIRED) && !(args->given & ((uint64_t)1 << i)))
            return hv_error_option(HV_ERR_INVALID, "{%s} is required", set->options[i].key);
    for (int k = 0; k < set->rule_count; ++k) {
        const hv_opt_rule *r = &set->rules[k];
        int a = hv_optargs_given(args, r->a), b = hv_optargs_given(args, r->b);
        int bad = 0;
        switch (r->kind) {
        case HV_RULE_EXCLUDES: bad = a && b; break;
        case HV_RULE_NEEDS: bad = a && !b; break;
        case HV_RULE_NEEDS_VALUE: bad = a && !value_listed(args, r->b, r->value); break;
        }
        if (bad) return rule_failed(r);
    }
    if (set->finish) {
        hv_status s = set->finish(args);
        if (s != HV_OK) return s;
    }
    return hv_options_check(set, args->opts);
}
