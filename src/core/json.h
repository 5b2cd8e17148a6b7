/* src/core/json.h - JSON through jansson, the one way hovox reads and writes JSON text (metadata
 * documents, manifests, --json output): parsing with positioned messages, typed member access
 * whose messages name the key, and one serialisation with fixed flags and round-trip numbers.
 * Not public API. */
#ifndef HOVOX_JSON_H
#define HOVOX_JSON_H

#include <jansson.h>

#include "core/internal.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- reading ------------------------------------------------------------------------------ */

/* Parse `len` bytes (no NUL needed) holding one JSON object or array. Duplicate keys, NUL
 * characters in strings, numbers out of range and nesting deeper than jansson's limit are
 * refused. `what` names the text in messages (a file, a metadata key). Errors:
 * HV_ERR_BAD_INPUT "<what>: line L, column C: <jansson's message>", HV_ERR_NOMEM. On success
 * *out is a new reference (json_decref). */
hv_status hv_json_parse(const char *text, size_t len, const char *what, json_t **out);

/* Typed members. `what` names the object in messages ("hovox.object.json: sources[2]"); each
 * records HV_ERR_BAD_INPUT "<what>: <key> is missing" or "<what>: <key> is a string, not a
 * number" and returns it. Numbers are JSON integers or reals (reals are finite: jansson
 * refuses overflow). */
hv_status hv_json_need(const json_t *obj, const char *key, json_type type, const char *what,
                       const json_t **out); /* JSON_REAL stands for any number */
hv_status hv_json_get_number(const json_t *obj, const char *key, const char *what, double *out);
/* An integral number in [lo, hi]. */
hv_status hv_json_get_int(const json_t *obj, const char *key, const char *what, long long lo,
                          long long hi, long long *out);
hv_status hv_json_get_string(const json_t *obj, const char *key, const char *what,
                             const char **out);
/* An array of exactly n numbers. */
hv_status hv_json_get_numbers(const json_t *obj, const char *key, const char *what, double *out,
                              size_t n);
/* A string that names a value of enum e; *out that value. Unknown names are refused (a
 * malformed document: HV_ERR_BAD_INPUT) with the list of valid ones. */
hv_status hv_json_get_name(const json_t *obj, const char *key, const char *what, const hv_enum_def *e, int *out);

/* ---- positions ---------------------------------------------------------------------------- */

/* jansson keeps no positions for the values it reads; files whose every value is checked after
 * parsing (tray jobs) still want "line L, column C" in each refusal. An index of a text that
 * hv_json_parse accepted: where each value, and each object member's key, starts. jansson reads
 * every string, number and literal (JSON_DECODE_ANY | JSON_DISABLE_EOF_CHECK), so keys are
 * matched decoded; the index itself only steps over whitespace, brackets, commas and colons.
 * Lines and columns are 1-based, columns count characters as jansson's own messages do. Values
 * are numbered in document order, the document itself 0. */
typedef struct hv_json_where hv_json_where;

/* Errors: HV_ERR_BAD_INPUT when the text is not one JSON value (parse it first), HV_ERR_NOMEM. */
hv_status hv_json_where_index(const char *text, size_t len, hv_json_where **out);
void hv_json_where_destroy(hv_json_where *w); /* NULL is fine */
/* The value of member `key` of object value v, or the i-th element of array value v; -1 when
 * there is none (also for v = -1, so lookups chain). */
int hv_json_where_member(const hv_json_where *w, int v, const char *key);
int hv_json_where_element(const hv_json_where *w, int v, size_t i);
/* Line and column of value v (of its key when of_key and v is an object member). Returns 0, or -1
 * when v is not a value of the index. */
int hv_json_where_at(const hv_json_where *w, int v, int of_key, int *line, int *column);

/* ---- writing ------------------------------------------------------------------------------ */

/* A double: integral values below 2^53 as JSON integers ("2", not "2.0"), other finite values
 * as reals, non-finite ones as null. NULL only when out of memory (as all builders here). */
json_t *hv_json_number(double v);
/* A float, as the double nearest its shortest decimal that reads back as the same float (at
 * most 9 significant digits: "0.3", not "0.300000012"; the f tables of grading sources,
 * colours). */
json_t *hv_json_float(float v);
/* An array of n doubles (hv_json_number each). */
json_t *hv_json_numbers(const double *v, size_t n);
/* A string; bytes that are not UTF-8 (a file name in another encoding) become U+FFFD. */
json_t *hv_json_text(const char *s);
/* Set obj[key] = value (stolen, also on failure). Returns 0, or -1 when value is NULL or memory
 * ran out: accumulate with |= and report HV_ERR_NOMEM once. */
int hv_json_set(json_t *obj, const char *key, json_t *value);

/* Serialise any JSON value on one line: jansson's default layout (", " and ": " separators,
 * keys in insertion order, UTF-8 as is, '/' unescaped) with each real in the shortest form
 * that reads back as the same double: jansson prints reals with JSON_REAL_PRECISION(17), which
 * always round-trips, and each is then shortened ("0.1", not "0.10000000000000001"; as
 * "%.*g" at the fewest digits, so 1e+21 keeps printf's exponent). Returns malloc'd text
 * (free()), or NULL with HV_ERR_NOMEM recorded. */
char *hv_json_dump(const json_t *doc);
/* An object laid out for people (manifest.json): one top-level member per line, indented by
 * two; a member holding a non-empty array of objects or arrays gets one element per line,
 * indented by four; everything else as hv_json_dump. Ends with a newline. */
char *hv_json_dump_lines(const json_t *doc);

#ifdef __cplusplus
}
#endif
#endif
