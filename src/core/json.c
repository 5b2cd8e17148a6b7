/* src/core/json.c - JSON through jansson (see json.h): positioned parse errors, typed members
 * with messages naming the key, and the one serialisation every writer uses. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"

/* ---- reading ------------------------------------------------------------------------------ */

hv_status hv_json_parse(const char *text, size_t len, const char *what, json_t **out)
{
    json_error_t e;
    *out = json_loadb(text, len, JSON_REJECT_DUPLICATES, &e);
    if (*out) return HV_OK;
    if (json_error_code(&e) == json_error_out_of_memory)
        return hv_error_set(HV_ERR_NOMEM, "%s: out of memory while reading JSON", what);
    return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d, column %d: %s", what, e.line, e.column, e.text);
}

static const char *type_name(const json_t *j)
{
    switch (json_typeof(j)) {
    case JSON_OBJECT: return "an object";
    case JSON_ARRAY: return "an array";
    case JSON_STRING: return "a string";
    case JSON_INTEGER:
    case JSON_REAL: return "a number";
    case JSON_TRUE: return "true";
    case JSON_FALSE: return "false";
    case JSON_NULL: return "null";
    }
    return "?";
}

hv_status hv_json_need(const json_t *obj, const char *key, json_type type, const char *what,
                       const json_t **out)
{
    static const char *const wanted[] = {"an object", "an array", "a string", "a number", "a number",
                                         "true", "false", "null"};
    *out = NULL;
    if (!json_is_object(obj)) return hv_error_set(HV_ERR_BAD_INPUT, "%s is %s, not an object", what, type_name(obj));
    const json_t *v = json_object_get(obj, key);
    if (!v) return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s is missing", what, key);
    int ok = type == JSON_REAL ? json_is_number(v) : json_typeof(v) == type;
    if (!ok)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s is %s, not %s", what, key, type_name(v),
                            (unsigned)type < HV_COUNT(wanted) ? wanted[type] : "?");
    *out = v;
    return HV_OK;
}

hv_status hv_json_get_number(const json_t *obj, const char *key, const char *what, double *out)
{
    const json_t *v;
    hv_status s = hv_json_need(obj, key, JSON_REAL, what, &v);
    if (s == HV_OK) *out = json_number_value(v);
    return s;
}

hv_status hv_json_get_int(const json_t *obj, const char *key, const char *what, long long lo,
                          long long hi, long long *out)
{
    double d;
    hv_status s = hv_json_get_number(obj, key, what, &d);
    if (s != HV_OK) return s;
    if (d != floor(d) || d < (double)lo || d > (double)hi)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s is %.17g, not an integer in [%lld, %lld]", what, key, d, lo, hi);
    *out = json_is_integer(json_object_get(obj, key)) ? json_integer_value(json_object_get(obj, key)) : (long long)d;
    return HV_OK;
}

hv_status hv_json_get_string(const json_t *obj, const char *key, const char *what, const char **out)
{
    const json_t *v;
    hv_status s = hv_json_need(obj, key, JSON_STRING, what, &v);
    *out = s == HV_OK ? json_string_value(v) : NULL;
    return s;
}

hv_status hv_json_get_numbers(const json_t *obj, const char *key, const char *what, double *out, size_t n)
{
    const json_t *a;
    hv_status s = hv_json_need(obj, key, JSON_ARRAY, what, &a);
    if (s != HV_OK) return s;
    if (json_array_size(a) != n)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s has %zu values, not %zu", what, key, json_array_size(a), n);
    for (size_t i = 0; i < n; ++i) {
        const json_t *e = json_array_get(a, i);
        if (!json_is_number(e))
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s[%zu] is %s, not a number", what, key, i, type_name(e));
        out[i] = json_number_value(e);
    }
    return HV_OK;
}

hv_status hv_json_get_name(const json_t *obj, const char *key, const char *what, const hv_enum_def *e, int *out)
{
    const char *v;
    hv_status s = hv_json_get_string(obj, key, what, &v);
    if (s != HV_OK) return s;
    /* a stored name hovox does not know is a malformed file, not a bad argument */
    if (hv_enum_parse(e, v, out) == HV_OK) return HV_OK;
    char list[512];
    return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s \"%s\" is not one of %s", what, key, v, hv_enum_list(e, list, sizeof list));
}

/* ---- writing ------------------------------------------------------------------------------ */

json_t *hv_json_number(double v)
{
    if (!isfinite(v)) return json_null();
    if (v == floor(v) && fabs(v) < 9007199254740992.0 && !(v == 0 && signbit(v)))
        return json_integer((json_int_t)v);
    return json_real(v);
}

json_t *hv_json_float(float v)
{
    if (!isfinite(v)) return json_null();
    char s[32];
    for (int p = 1; p <= 9; ++p) { /* 9 digits always read back as the same float */
        snprintf(s, sizeof s, "%.*g", p, (double)v);
        if (strtof(s, NULL) == v) break;
    }
    return hv_json_number(strtod(s, NULL));
}

json_t *hv_json_numbers(const double *v, size_t n)
{
    json_t *a = json_array();
    int failed = !a;
    for (size_t i = 0; i < n && !failed; ++i) failed = json_array_append_new(a, hv_json_number(v[i])) != 0;
    if (failed) {
        json_decref(a);
        return NULL;
    }
    return a;
}

/* Length of the well-formed UTF-8 sequence at s (RFC 3629: no overlongs, surrogates or code
 * points above U+10FFFF), 0 when there is none. */
static size_t utf8_length(const unsigned char *s)
{
    unsigned char c = s[0];
    if (c < 0x80) return 1;
    size_t n;
    unsigned char lo = 0x80, hi = 0xBF;
    if (c >= 0xC2 && c <= 0xDF) n = 2;
    else if (c >= 0xE0 && c <= 0xEF) n = 3, lo = c == 0xE0 ? 0xA0 : 0x80, hi = c == 0xED ? 0x9F : 0xBF;
    else if (c >= 0xF0 && c <= 0xF4) n = 4, lo = c == 0xF0 ? 0x90 : 0x80, hi = c == 0xF4 ? 0x8F : 0xBF;
    else return 0;
    if (s[1] < lo || s[1] > hi) return 0;
    for (size_t i = 2; i < n; ++i)
        if (s[i] < 0x80 || s[i] > 0xBF) return 0;
    return n;
}

json_t *hv_json_text(const char *s)
{
    json_t *j = json_string(s);
    if (j || !s) return j;
    /* not UTF-8: keep the well-formed sequences, one U+FFFD per stray byte */
    hv_buf b;
    hv_buf_init(&b);
    for (const unsigned char *p = (const unsigned char *)s; *p;) {
        size_t n = utf8_length(p);
        if (n) hv_buf_append(&b, (const char *)p, n);
        else hv_buf_puts(&b, "\xEF\xBF\xBD");
        p += n ? n : 1;
    }
    j = b.failed ? NULL : json_string(b.data);
    hv_buf_free(&b);
    return j;
}

int hv_json_set(json_t *obj, const char *key, json_t *value)
{
    return json_object_set_new(obj, key, value) != 0 ? -1 : 0;
}

/* The shortest "%.*g" form of v (1..17 significant digits) that reads back as v. */
static void shortest(char s[40], double v)
{
    for (int p = 1; p <= 17; ++p) {
        snprintf(s, 40, "%.*g", p, v);
        if (strtod(s, NULL) == v) return;
    }
}

char *hv_json_dump(const json_t *doc)
{
    /* jansson prints every real at one precision; at 17 digits each reads back exactly, and
     * then each is rewritten in its shortest such form ("0.1", not "0.10000000000000001"):
     * a lexical pass over jansson's output that leaves strings alone */
    char *raw = json_dumps(doc, JSON_ENCODE_ANY | JSON_REAL_PRECISION(17));
    hv_buf b;
    hv_buf_init(&b);
    int in_string = 0;
    for (const char *p = raw; p && *p;) {
        const char *q = p + 1;
        if (in_string) {
            if (*p == '\\' && p[1]) ++q;
            else if (*p == '"') in_string = 0;
        } else if (*p == '"') {
            in_string = 1;
        } else if (*p == '-' || (*p >= '0' && *p <= '9')) {
            while (*q && strchr("0123456789+-.eE", *q)) ++q;
            if (memchr(p, '.', (size_t)(q - p)) || memchr(p, 'e', (size_t)(q - p)) || memchr(p, 'E', (size_t)(q - p))) {
                char num[40];
                shortest(num, strtod(p, NULL));
                hv_buf_puts(&b, num);
                p = q;
                continue;
            }
        }
        hv_buf_append(&b, p, (size_t)(q - p));
        p = q;
    }
    free(raw);
    if (!raw || b.failed) {
        hv_buf_free(&b);
        hv_error_set(HV_ERR_NOMEM, "out of memory (writing JSON)");
        return NULL;
    }
    return b.data;
}

/* Append hv_json_dump(v) to b. */
static void put(hv_buf *b, const json_t *v)
{
    char *s = v ? hv_json_dump(v) : NULL;
    if (!s) b->failed = 1;
    else hv_buf_puts(b, s);
    free(s);
}

char *hv_json_dump_lines(const json_t *doc)
{
    hv_buf b;
    hv_buf_init(&b);
    hv_buf_puts(&b, "{");
    const char *key;
    json_t *v;
    int first = 1;
    json_object_foreach((json_t *)doc, key, v) {
        json_t *k = hv_json_text(key);
        hv_buf_puts(&b, first ? "\n  " : ",\n  ");
        first = 0;
        put(&b, k);
        json_decref(k);
        hv_buf_puts(&b, ": ");
        json_t *e0 = json_is_array(v) ? json_array_get(v, 0) : NULL;
        if (e0 && (json_is_object(e0) || json_is_array(e0))) {
            size_t i;
            json_t *e;
            json_array_foreach(v, i, e) {
                hv_buf_puts(&b, i ? ",\n    " : "[\n    ");
                put(&b, e);
            }
            hv_buf_puts(&b, "\n  ]");
        } else {
            put(&b, v);
        }
    }
    hv_buf_puts(&b, first ? "}\n" : "\n}\n");
    if (b.failed) {
        hv_buf_free(&b);
        hv_error_set(HV_ERR_NOMEM, "out of memory (writing JSON)");
        return NULL;
    }
    return b.data;
}
