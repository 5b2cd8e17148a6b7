/* slicing/tray_job.c - tray job files (hovox/tray.h, README "Tray jobs"): JSON read by jansson,
 * every key through the tray's and the parts' option sets, so a job file takes what the CLI
 * and Lua take. Every refusal names file, line and column: of a syntax error from jansson, of a
 * value or key from the position index of src/core/json.c. A parser of files from others: fuzzed
 * (tests/fuzz/fuzz_tray_job.c). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "core/json.h"
#include "hovox/tray.h"
#include "layers_internal.h"

#define MAX_JOB (16u << 20)

/* ---- reading ------------------------------------------------------------------------------- */

typedef struct reader {
    const char *name, *base;
    hv_json_where *where; /* positions of the values */
    hv_tray *tray;
} reader;

/* "name: line L, column C: " + the message already set; the position of value v (of its key) */
static hv_status at(const reader *r, int v, int of_key, hv_status s)
{
    if (s == HV_ERR_NOMEM) return s;
    char msg[1024];
    snprintf(msg, sizeof msg, "%s", hv_last_error()); /* plain: options spelt as the file's keys */
    int line, col;
    hv_status code = s == HV_ERR_LIMIT ? HV_ERR_LIMIT : HV_ERR_BAD_INPUT; /* a limit stays one (exit 3) */
    if (hv_json_where_at(r->where, v, of_key, &line, &col) != 0) return hv_error_set(code, "%s: %s", r->name, msg);
    return hv_error_set(code, "%s: line %d, column %d: %s", r->name, line, col, msg);
}

static const char *type_name(const json_t *v)
{
    switch (json_typeof(v)) {
    case JSON_OBJECT: return "an object";
    case JSON_ARRAY: return "an array";
    case JSON_STRING: return "a string";
    case JSON_INTEGER:
    case JSON_REAL: return "a number";
    case JSON_TRUE:
    case JSON_FALSE: return "a boolean";
    default: return "null";
    }
}

/* A string that stays alive as long as the tray (paths resolved against the job's directory). */
static const char *keep(reader *r, const char *s, int is_path)
{
    char buf[4400];
    if (is_path && s[0] != '/' && r->base && *r->base) snprintf(buf, sizeof buf, "%s/%s", r->base, s);
    else snprintf(buf, sizeof buf, "%s", s);
    return hv_tray_keep(r->tray, buf);
}

/* One JSON value (value `node` of the index) into option `key` of `args` (set through the option set). */
static hv_status set_value(reader *r, hv_optargs *args, const char *key, const json_t *v, int node)
{
    const hv_option *o = hv_option_find(args->set, key);
    hv_opt_value ov = {HV_VALUE_TEXT, NULL, NULL, 0, 0};
    double nums[64];
    hv_status s;
    if (!o) {
        char list[1024];
        size_t n = 0;
        list[0] = '\0';
        for (int i = 0; i < args->set->count && n < sizeof list; ++i)
            n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", i ? ", " : "", args->set->options[i].key);
        s = hv_error_set(HV_ERR_INVALID, "unknown key '%s' (keys: %s%s)", key, list,
                         args->set == hv_tray_option_set() ? ", parts, schema" : "");
        return at(r, node, 1, s);
    }
    int is_path = (o->kind == HV_OPT_STRING && (strcmp(key, "model") == 0 || strcmp(key, "mesh") == 0)) ||
                  (o->flags & (HV_OPT_OUT_PATH | HV_OPT_IN_PATH)); /* also a custom option's (icc) */
    switch (json_typeof(v)) {
    case JSON_STRING:
        ov.text = keep(r, json_string_value(v), is_path);
        if (!ov.text) return HV_ERR_NOMEM;
        break;
    case JSON_INTEGER:
    case JSON_REAL:
        if (o->kind == HV_OPT_ENUM) {
            char t[64];
            snprintf(t, sizeof t, "%.17g", json_number_value(v));
            ov.text = keep(r, t, 0);
        } else {
            ov.type = HV_VALUE_NUMBERS;
            nums[0] = json_number_value(v);
            ov.numbers = nums;
            ov.n = 1;
        }
        break;
    case JSON_TRUE:
    case JSON_FALSE:
        ov.type = HV_VALUE_BOOL;
        ov.boolean = json_is_true(v);
        break;
    case JSON_ARRAY: {
        size_t n = json_array_size(v);
        if (n > 0 && json_is_string(json_array_get(v, 0)) && (o->flags & HV_OPT_REPEAT)) {
            for (size_t i = 0; i < n; ++i)
                if ((s = set_value(r, args, key, json_array_get(v, i), hv_json_where_element(r->where, node, i))) != HV_OK)
                    return s;
            return HV_OK;
        }
        if (o->kind == HV_OPT_STRING && n > 0) { /* a list of integers for a text option: "A,B,..." (labels) */
            hv_buf b;
            hv_buf_init(&b);
            for (size_t i = 0; i < n; ++i) {
                const json_t *e = json_array_get(v, i);
                if (!json_is_integer(e)) {
                    hv_buf_free(&b);
                    return at(r, hv_json_where_element(r->where, node, i), 0,
                              hv_error_set(HV_ERR_INVALID, "%s must be a list of integers; item %zu is %s", key, i + 1,
                                           json_is_number(e) ? "not an integer" : type_name(e)));
                }
                hv_buf_printf(&b, "%s%lld", i ? "," : "", (long long)json_integer_value(e));
            }
            ov.text = b.failed ? NULL : keep(r, b.data, 0);
            hv_buf_free(&b);
            if (!ov.text) return HV_ERR_NOMEM;
            s = hv_optargs_set(args, key, &ov);
            return s == HV_OK ? s : at(r, node, 0, s);
        }
        if (n > 64) return at(r, node, 0, hv_error_set(HV_ERR_INVALID, "%s has %zu values (at most 64)", key, n));
        for (size_t i = 0; i < n; ++i) {
            const json_t *e = json_array_get(v, i);
            if (!json_is_number(e))
                return at(r, hv_json_where_element(r->where, node, i), 0,
                          hv_error_set(HV_ERR_INVALID, "%s must be a list of numbers; item %zu is %s", key, i + 1,
                                       type_name(e)));
            nums[i] = json_number_value(e);
        }
        ov.type = HV_VALUE_NUMBERS;
        ov.numbers = nums;
        ov.n = (int)n;
        break;
    }
    case JSON_OBJECT:
        if (o->flags & HV_OPT_REPEAT) { /* {"A": "VeroCyan-V"}: A=VeroCyan-V per member */
            const char *k;
            json_t *e;
            json_object_foreach((json_t *)v, k, e) {
                char pair[512];
                int sub = hv_json_where_member(r->where, node, k);
                if (!json_is_string(e))
                    return at(r, sub, 0, hv_error_set(HV_ERR_INVALID, "%s.%s must be a string, got %s", key, k, type_name(e)));
                snprintf(pair, sizeof pair, "%s=%s", k, json_string_value(e));
                hv_opt_value pv = {HV_VALUE_TEXT, keep(r, pair, 0), NULL, 0, 0};
                if (!pv.text) return HV_ERR_NOMEM;
                if ((s = hv_optargs_set(args, key, &pv)) != HV_OK) return at(r, sub, 0, s);
            }
            return HV_OK;
        }
        /* fall through */
    default:
        return at(r, node, 0, hv_error_set(HV_ERR_INVALID, "%s cannot be %s", key, type_name(v)));
    }
    s = hv_optargs_set(args, key, &ov);
    return s == HV_OK ? s : at(r, node, 0, s);
}

/* "name: line L, column C" of value v (of its key), kept by the tray; NULL when not known */
static const char *place_of(reader *r, int v, int of_key)
{
    int line, col;
    char buf[300];
    if (v < 0 || hv_json_where_at(r->where, v, of_key, &line, &col) != 0) return NULL;
    snprintf(buf, sizeof buf, "%s: line %d, column %d", r->name, line, col);
    return keep(r, buf, 0);
}

/* Where each of the part's "materials" pairs is (an object's keys, an array's elements, a string),
 * in the order they were set: a body the mesh lacks is reported there. */
static void pair_places(reader *r, const json_t *v, int node, int n, const char **out)
{
    const json_t *m = json_object_get(v, "materials");
    int mn = hv_json_where_member(r->where, node, "materials");
    int k = 0;
    if (json_is_object(m)) {
        const char *key;
        json_t *e;
        json_object_foreach((json_t *)m, key, e) {
            if (k < n) out[k] = place_of(r, hv_json_where_member(r->where, mn, key), 1);
            ++k;
        }
    } else if (json_is_array(m)) {
        for (; k < n && (size_t)k < json_array_size(m); ++k) out[k] = place_of(r, hv_json_where_element(r->where, mn, (size_t)k), 0);
    } else if (m && n > 0) {
        out[0] = place_of(r, mn, 0);
    }
}

static hv_status read_part(reader *r, const json_t *v, int node)
{
    if (!json_is_object(v))
        return at(r, node, 0, hv_error_set(HV_ERR_INVALID, "a part must be an object, got %s", type_name(v)));
    hv_tray_part p;
    hv_optargs args;
    hv_optargs_begin(&args, hv_tray_part_option_set(), &p);
    const char *k;
    json_t *e;
    hv_status s = HV_OK;
    json_object_foreach((json_t *)v, k, e)
        if ((s = set_value(r, &args, k, e, hv_json_where_member(r->where, node, k))) != HV_OK) return s;
    if ((s = hv_optargs_finish(&args)) != HV_OK) return at(r, node, 0, s);
    int line, col;
    char where[300];
    if (hv_json_where_at(r->where, node, 0, &line, &col) == 0)
        snprintf(where, sizeof where, "%s: line %d, column %d", r->name, line, col);
    else snprintf(where, sizeof where, "%s", r->name);
    const char *pair_where[HV_BODY_MATERIALS_MAX] = {NULL};
    pair_places(r, v, node, p.materials.n, pair_where);
    return hv_tray_add_at(r->tray, &p, where, pair_where);
}

hv_status hv_tray_parse_job(const char *text, size_t size, const char *name, const char *base, hv_tray **out,
                            hv_tray_options *o)
{
    *out = NULL;
    const char *nul = memchr(text, '\0', size);
    if (nul) { /* a job file is text; jansson would read a NUL byte as the end */
        int line = 1;
        const char *ls = text;
        for (const char *p = text; p < nul; ++p)
            if (*p == '\n') line++, ls = p + 1;
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d, column %d: a NUL byte (a job file is text)", name, line,
                            (int)(nul - ls) + 1);
    }
    json_t *doc = NULL;
    hv_status s = hv_json_parse(text, size, name, &doc);
    if (s != HV_OK) return s;
    reader r;
    memset(&r, 0, sizeof r);
    r.name = name;
    r.base = base;
    s = hv_json_where_index(text, size, &r.where);
    if (s == HV_OK && !json_is_object(doc))
        s = at(&r, 0, 0, hv_error_set(HV_ERR_INVALID, "a tray job is a JSON object, got %s", type_name(doc)));
    if (s == HV_OK) s = hv_tray_create(&r.tray);
    hv_optargs args;
    hv_optargs_begin(&args, hv_tray_option_set(), o);
    const json_t *parts = s == HV_OK ? json_object_get(doc, "parts") : NULL;
    const json_t *schema = s == HV_OK ? json_object_get(doc, "schema") : NULL;
    if (s == HV_OK && schema && !(json_is_integer(schema) && json_integer_value(schema) == 1))
        s = at(&r, hv_json_where_member(r.where, 0, "schema"), 0, hv_error_set(HV_ERR_BAD_INPUT, "schema must be 1 (this hovox reads tray jobs of schema 1)"));
    const char *k;
    json_t *e;
    if (s == HV_OK) {
        json_object_foreach(doc, k, e) {
            if (strcmp(k, "parts") == 0 || strcmp(k, "schema") == 0) continue;
            if ((s = set_value(&r, &args, k, e, hv_json_where_member(r.where, 0, k))) != HV_OK) break;
        }
    }
    int pn = hv_json_where_member(r.where, 0, "parts");
    if (s == HV_OK && (s = hv_optargs_finish(&args)) != HV_OK) s = at(&r, 0, 0, s);
    if (s == HV_OK && !parts) s = at(&r, 0, 0, hv_error_set(HV_ERR_INVALID, "a tray job needs \"parts\": [...]"));
    if (s == HV_OK && !json_is_array(parts))
        s = at(&r, pn, 0, hv_error_set(HV_ERR_INVALID, "parts must be an array, got %s", type_name(parts)));
    if (s == HV_OK && json_array_size(parts) == 0) s = at(&r, pn, 0, hv_error_set(HV_ERR_INVALID, "parts is empty"));
    /* a tray holds at most HV_TRAY_MAX_PARTS placed parts: a longer list is refused before any part
     * is read (20,000 parts took 18 s to be refused) */
    if (s == HV_OK && json_array_size(parts) > HV_TRAY_MAX_PARTS)
        s = at(&r, pn, 0,
               hv_error_set(HV_ERR_LIMIT, "%zu parts, more than a tray holds (%d)", json_array_size(parts), HV_TRAY_MAX_PARTS));
    for (size_t i = 0; s == HV_OK && i < json_array_size(parts); ++i)
        s = read_part(&r, json_array_get(parts, i), hv_json_where_element(r.where, pn, i));
    json_decref(doc);
    hv_json_where_destroy(r.where);
    if (s != HV_OK) {
        hv_tray_destroy(r.tray);
        return s;
    }
    *out = r.tray;
    return HV_OK;
}

hv_status hv_tray_load_job(const char *path, hv_tray **out, hv_tray_options *o)
{
    *out = NULL;
    char *text = NULL;
    size_t size = 0;
    hv_status s = hv_read_file(path, MAX_JOB, &text, &size);
    if (s == HV_OK) hv_input_note(path);
    if (s != HV_OK) return s;
    char base[4096];
    snprintf(base, sizeof base, "%s", path);
    char *slash = strrchr(base, '/');
    if (slash) *slash = '\0';
    else base[0] = '\0';
    s = hv_tray_parse_job(text, size, path, base, out, o);
    free(text);
    return s;
}
