/* src/core/json.c - JSON through jansson (see json.h): positioned parse errors, typed members
 * with messages naming the key, and the one serialisation every writer uses. */
#include <limits.h>
#include <math.h>
#include <stdint.h>
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

/* ---- positions ------------------------------------------------------------------------------ */

typedef struct where_value {
    int line, col;   /* the value */
    int kline, kcol; /* its key (members) */
    int first, last, next; /* children in order; the next sibling; -1: none */
    size_t key;      /* offset of the member's key in keys, or SIZE_MAX */
} where_value;

struct hv_json_where {
    where_value *v;
    size_t n, cap;
    char *keys;
    size_t nkeys, capkeys;
};

typedef struct walker {
    hv_json_where *w;
    const char *s;
    size_t len, at;
    int line, col;
} walker;

static void walk_to(walker *k, size_t to)
{
    for (; k->at < to; ++k->at) {
        unsigned char c = (unsigned char)k->s[k->at];
        if (c == '\n') {
            k->line++;
            k->col = 1;
        } else if ((c & 0xC0) != 0x80) {
            k->col++; /* a character starts: columns as jansson counts them */
        }
    }
}

static char walk_ws(walker *k)
{
    size_t i = k->at;
    while (i < k->len && (k->s[i] == ' ' || k->s[i] == '\t' || k->s[i] == '\n' || k->s[i] == '\r')) ++i;
    walk_to(k, i);
    return i < k->len ? k->s[i] : '\0';
}

static hv_status walk_bad(const walker *k)
{
    return hv_error_set(HV_ERR_BAD_INPUT, "line %d, column %d: not JSON", k->line, k->col);
}

/* A string, number or literal, read by jansson; *out (if asked) the value, a new reference. */
static hv_status walk_token(walker *k, json_t **out)
{
    json_error_t e;
    json_t *j = json_loadb(k->s + k->at, k->len - k->at, JSON_DECODE_ANY | JSON_DISABLE_EOF_CHECK, &e);
    if (!j) return json_error_code(&e) == json_error_out_of_memory ? HV_ERR_NOMEM : walk_bad(k);
    walk_to(k, k->at + (size_t)e.position);
    if (out) *out = j;
    else json_decref(j);
    return HV_OK;
}

static hv_status walk_value(walker *k, int parent, size_t key, int kline, int kcol, int depth)
{
    hv_json_where *w = k->w;
    char c = walk_ws(k);
    if (depth > 2048 || w->n >= INT_MAX) return walk_bad(k); /* jansson's own depth limit */
    if (hv_grow((void **)&w->v, &w->cap, w->n + 1, sizeof *w->v) != HV_OK) return HV_ERR_NOMEM;
    int me = (int)w->n++;
    w->v[me] = (where_value){k->line, k->col, kline, kcol, -1, -1, -1, key};
    if (parent >= 0) {
        if (w->v[parent].last >= 0) w->v[w->v[parent].last].next = me;
        else w->v[parent].first = me;
        w->v[parent].last = me;
    }
    if (c != '{' && c != '[') return c ? walk_token(k, NULL) : walk_bad(k);
    char close = c == '{' ? '}' : ']';
    walk_to(k, k->at + 1);
    if (walk_ws(k) == close) {
        walk_to(k, k->at + 1);
        return HV_OK;
    }
    for (;;) {
        hv_status s;
        size_t at = SIZE_MAX;
        int kl = 0, kc = 0;
        if (c == '{') { /* "key": the key decoded, kept for lookups */
            json_t *name = NULL;
            kl = k->line;
            kc = k->col;
            if (walk_ws(k) != '"') return walk_bad(k);
            if ((s = walk_token(k, &name)) != HV_OK) return s;
            size_t n = strlen(json_string_value(name)) + 1;
            if (hv_grow((void **)&w->keys, &w->capkeys, w->nkeys + n, 1) != HV_OK) {
                json_decref(name);
                return HV_ERR_NOMEM;
            }
            memcpy(w->keys + w->nkeys, json_string_value(name), n);
            json_decref(name);
            at = w->nkeys;
            w->nkeys += n;
            if (walk_ws(k) != ':') return walk_bad(k);
            walk_to(k, k->at + 1);
        }
        if ((s = walk_value(k, me, at, kl, kc, depth + 1)) != HV_OK) return s;
        char after = walk_ws(k);
        walk_to(k, k->at + 1);
        if (after == close) return HV_OK;
        if (after != ',') return walk_bad(k);
        walk_ws(k);
    }
}

hv_status hv_json_where_index(const char *text, size_t len, hv_json_where **out)
{
    *out = NULL;
    hv_json_where *w = calloc(1, sizeof *w);
    if (!w) return HV_ERR_NOMEM;
    walker k = {w, text, len, 0, 1, 1};
    hv_status s = walk_value(&k, -1, SIZE_MAX, 0, 0, 0);
    if (s == HV_OK && walk_ws(&k)) s = walk_bad(&k);
    if (s != HV_OK) {
        hv_json_where_destroy(w);
        return s;
    }
    *out = w;
    return HV_OK;
}

void hv_json_where_destroy(hv_json_where *w)
{
    if (!w) return;
    free(w->v);
    free(w->keys);
    free(w);
}

int hv_json_where_member(const hv_json_where *w, int v, const char *key)
{
    if (!w || v < 0 || (size_t)v >= w->n) return -1;
    for (int c = w->v[v].first; c >= 0; c = w->v[c].next)
        if (w->v[c].key != SIZE_MAX && strcmp(w->keys + w->v[c].key, key) == 0) return c;
    return -1;
}

int hv_json_where_element(const hv_json_where *w, int v, size_t i)
{
    if (!w || v < 0 || (size_t)v >= w->n) return -1;
    int c = w->v[v].first;
    for (; c >= 0 && i > 0; --i) c = w->v[c].next;
    return c >= 0 && w->v[c].key == SIZE_MAX ? c : -1;
}

int hv_json_where_at(const hv_json_where *w, int v, int of_key, int *line, int *column)
{
    if (!w || v < 0 || (size_t)v >= w->n) return -1;
    const where_value *x = &w->v[v];
    int key = of_key && x->key != SIZE_MAX;
    *line = key ? x->kline : x->line;
    *column = key ? x->kcol : x->col;
    return 0;
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
