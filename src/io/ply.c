/* src/io/ply.c - PLY input (Turk's polygon file format 1.0): ASCII, binary little- and
 * big-endian. The vertex element's x, y, z (any scalar type), its colour red, green, blue
 * [alpha] (uchar, or float/double in [0, 1]) and the face element's vertex index list (any
 * integer types) are read; every other property and element is skipped by its size. Counts in
 * the header are checked against the bytes that follow before anything is allocated. Polygons
 * are fan-triangulated; one body named after the file; vertex colours become corner colours. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "io_internal.h"

#define PLY_MAX_HEADER ((size_t)1 << 20)
#define PLY_MAX_PROPS 1024
#define PLY_MAX_ELEMENTS 256

enum { T_INT8, T_UINT8, T_INT16, T_UINT16, T_INT32, T_UINT32, T_FLOAT32, T_FLOAT64, T_NONE };
static const char *const k_type_names[][2] = {{"char", "int8"},   {"uchar", "uint8"},   {"short", "int16"},
                                             {"ushort", "uint16"}, {"int", "int32"},     {"uint", "uint32"},
                                             {"float", "float32"}, {"double", "float64"}};
static const int k_type_size[] = {1, 1, 2, 2, 4, 4, 4, 8};

enum { F_ASCII, F_LE, F_BE };

typedef struct ply_prop {
    int type;       /* of the value, or of the list items */
    int count_type; /* T_NONE: a scalar */
    char name[64];
} ply_prop;

typedef struct ply_elem {
    char name[64];
    uint64_t count;
    ply_prop *props;
    size_t nprops, cap;
    int role;       /* 0 other, 1 vertex, 2 face */
    int xyz[3];     /* vertex: property of x, y, z */
    int rgba[4];    /* vertex: property of red, green, blue, alpha, or -1 */
    int indices;    /* face: the list property */
} ply_elem;

typedef struct ply_reader {
    const char *name;
    const unsigned char *d, *end, *p; /* data; p: the cursor */
    int format;
    size_t line;                      /* ASCII: line of the cursor */
    ply_elem elems[PLY_MAX_ELEMENTS];
    size_t nelems;
    ply_elem *vertex, *face;
    float *xyz;
    uint32_t *colour; /* per vertex 0xRRGGBBAA, when the vertices have colours */
    uint32_t *tri;
    size_t nt, tcap;
} ply_reader;

static int type_of(const char *s, size_t n)
{
    for (int t = 0; t < T_NONE; ++t)
        for (int k = 0; k < 2; ++k)
            if (strlen(k_type_names[t][k]) == n && memcmp(k_type_names[t][k], s, n) == 0) return t;
    return T_NONE;
}

static int is_integer(int t) { return t <= T_UINT32; }

/* ---- header ------------------------------------------------------------------------------ */

/* Words of a header line, at most `max`; returns their number. */
static size_t split(const char *s, const char *e, const char **w, size_t *wl, size_t max)
{
    size_t n = 0;
    while (s < e) {
        while (s < e && (*s == ' ' || *s == '\t' || *s == '\r')) ++s;
        if (s == e) break;
        const char *t = s;
        while (s < e && *s != ' ' && *s != '\t' && *s != '\r') ++s;
        if (n < max) {
            w[n] = t;
            wl[n] = (size_t)(s - t);
        }
        ++n;
    }
    return n;
}

static int is_word(const char *w, size_t n, const char *word)
{
    return n == strlen(word) && memcmp(w, word, n) == 0;
}

static hv_status header_error(const ply_reader *r, size_t line, const char *what, const char *w, size_t n)
{
    char q[72];
    return hv_error_set(HV_ERR_BAD_INPUT, "%s: header line %zu: %s '%s'", r->name, line, what,
                        hv_quote(q, sizeof q, w, n));
}

static hv_status header_property(ply_reader *r, size_t line, const char **w, const size_t *wl, size_t n,
                                  const char *ls, size_t ll)
{
    if (r->nelems == 0) return header_error(r, line, "property before any element:", w[0], wl[0]);
    ply_elem *el = &r->elems[r->nelems - 1];
    ply_prop pr = {T_NONE, T_NONE, ""};
    size_t name_at;
    if (n >= 2 && is_word(w[1], wl[1], "list")) {
        if (n != 5) return header_error(r, line, "expected 'property list COUNT_TYPE ITEM_TYPE NAME', got", ls, ll);
        pr.count_type = type_of(w[2], wl[2]);
        pr.type = type_of(w[3], wl[3]);
        if (pr.count_type == T_NONE) return header_error(r, line, "unknown list count type", w[2], wl[2]);
        if (pr.type == T_NONE) return header_error(r, line, "unknown list item type", w[3], wl[3]);
        if (!is_integer(pr.count_type))
            return header_error(r, line, "a list count must have an integer type, not", w[2], wl[2]);
        name_at = 4;
    } else {
        if (n != 3) return header_error(r, line, "expected 'property TYPE NAME', got", ls, ll);
        pr.type = type_of(w[1], wl[1]);
        if (pr.type == T_NONE) return header_error(r, line, "unknown property type", w[1], wl[1]);
        name_at = 2;
    }
    if (wl[name_at] >= sizeof pr.name) return header_error(r, line, "property name too long:", w[name_at], wl[name_at]);
    memcpy(pr.name, w[name_at], wl[name_at]);
    for (size_t i = 0; i < el->nprops; ++i)
        if (strcmp(el->props[i].name, pr.name) == 0)
            return header_error(r, line, "property declared twice:", w[name_at], wl[name_at]);
    if (el->nprops == PLY_MAX_PROPS)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: header line %zu: element '%s' has more than %d properties",
                            r->name, line, el->name, PLY_MAX_PROPS);
    hv_status s = hv_grow((void **)&el->props, &el->cap, el->nprops + 1, sizeof *el->props);
    if (s != HV_OK) return s;
    el->props[el->nprops++] = pr;
    return HV_OK;
}

static hv_status header_element(ply_reader *r, size_t line, const char **w, const size_t *wl, size_t n,
                                 const char *ls, size_t ll)
{
    if (n != 3) return header_error(r, line, "expected 'element NAME COUNT', got", ls, ll);
    if (r->nelems == PLY_MAX_ELEMENTS)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: header line %zu: more than %d elements", r->name, line,
                            PLY_MAX_ELEMENTS);
    ply_elem *el = &r->elems[r->nelems];
    memset(el, 0, sizeof *el);
    if (wl[1] >= sizeof el->name) return header_error(r, line, "element name too long:", w[1], wl[1]);
    memcpy(el->name, w[1], wl[1]);
    uint64_t c = 0;
    for (size_t i = 0; i < wl[2]; ++i) {
        if (w[2][i] < '0' || w[2][i] > '9' || c > (UINT64_MAX - 9) / 10)
            return header_error(r, line, "element count is not a count:", w[2], wl[2]);
        c = c * 10 + (uint64_t)(w[2][i] - '0');
    }
    el->count = c;
    for (size_t i = 0; i < r->nelems; ++i)
        if (strcmp(r->elems[i].name, el->name) == 0)
            return header_error(r, line, "element declared twice:", w[1], wl[1]);
    r->nelems++;
    return HV_OK;
}

/* The roles of the elements: vertex (x, y, z) and face (vertex_indices or vertex_index). */
static hv_status roles(ply_reader *r)
{
    for (size_t i = 0; i < r->nelems; ++i) {
        ply_elem *el = &r->elems[i];
        if (strcmp(el->name, "vertex") == 0) {
            el->role = 1;
            r->vertex = el;
            for (int a = 0; a < 3; ++a) {
                static const char *const axis[] = {"x", "y", "z"};
                el->xyz[a] = -1;
                for (size_t k = 0; k < el->nprops; ++k)
                    if (strcmp(el->props[k].name, axis[a]) == 0) el->xyz[a] = (int)k;
                if (el->xyz[a] < 0)
                    return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: element vertex has no property %s",
                                        r->name, axis[a]);
                if (el->props[el->xyz[a]].count_type != T_NONE)
                    return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: vertex property %s is a list, not a scalar",
                                        r->name, axis[a]);
            }
            static const char *const chan[] = {"red", "green", "blue", "alpha"};
            int found = 0;
            for (int c = 0; c < 4; ++c) {
                el->rgba[c] = -1;
                for (size_t k = 0; k < el->nprops; ++k)
                    if (strcmp(el->props[k].name, chan[c]) == 0) el->rgba[c] = (int)k;
                if (el->rgba[c] < 0) continue;
                const ply_prop *pr = &el->props[el->rgba[c]];
                if (pr->count_type != T_NONE || !(pr->type == T_UINT8 || pr->type == T_FLOAT32 || pr->type == T_FLOAT64))
                    return hv_error_set(HV_ERR_BAD_INPUT,
                                        "%s: header: vertex colour %s must be a uchar, float or double scalar",
                                        r->name, chan[c]);
                if (c < 3) ++found;
            }
            if (found != 0 && found != 3)
                return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: vertex colour needs red, green and blue (%s missing)",
                                    r->name, el->rgba[0] < 0 ? "red" : el->rgba[1] < 0 ? "green" : "blue");
            if (found == 0 && el->rgba[3] >= 0)
                return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: vertex alpha without red, green and blue", r->name);
        } else if (strcmp(el->name, "face") == 0) {
            el->role = 2;
            r->face = el;
            el->indices = -1;
            for (size_t k = 0; k < el->nprops; ++k)
                if (strcmp(el->props[k].name, "vertex_indices") == 0 || strcmp(el->props[k].name, "vertex_index") == 0)
                    el->indices = (int)k;
            if (el->indices < 0)
                return hv_error_set(HV_ERR_BAD_INPUT,
                                    "%s: header: element face has no property list vertex_indices (or "
                                    "vertex_index)",
                                    r->name);
            const ply_prop *pr = &el->props[el->indices];
            if (pr->count_type == T_NONE || !is_integer(pr->type))
                return hv_error_set(HV_ERR_BAD_INPUT,
                                    "%s: header: face property %s must be a list of integers (for example "
                                    "'property list uchar int %s')",
                                    r->name, pr->name, pr->name);
        }
    }
    if (!r->vertex) return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: no element vertex", r->name);
    if (!r->face)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: no element face (a point cloud has no surface)", r->name);
    return HV_OK;
}

static hv_status parse_header(ply_reader *r)
{
    const char *d = (const char *)r->d, *end = (const char *)r->end;
    const char *p = d;
    size_t line = 0;
    int have_format = 0;
    for (;;) {
        ++line;
        const char *eol = memchr(p, '\n', (size_t)(end - p));
        if (!eol || (size_t)(eol - d) > PLY_MAX_HEADER)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: header has no end_header line%s", r->name,
                                eol ? " within its first MiB" : "");
        const char *w[6];
        size_t wl[6];
        size_t n = split(p, eol, w, wl, 6);
        const char *ls = p;
        p = eol + 1;
        if (line == 1) {
            if (n != 1 || !is_word(w[0], wl[0], "ply"))
                return hv_error_set(HV_ERR_BAD_INPUT, "%s: not a PLY file: the first line is not 'ply'", r->name);
            continue;
        }
        if (n == 0) continue;
        if (is_word(w[0], wl[0], "comment") || is_word(w[0], wl[0], "obj_info")) continue;
        if (is_word(w[0], wl[0], "format")) {
            if (have_format) return header_error(r, line, "second format line:", ls, (size_t)(eol - ls));
            if (n != 3) return header_error(r, line, "expected 'format ascii|binary_little_endian|binary_big_endian 1.0', got", ls, (size_t)(eol - ls));
            if (is_word(w[1], wl[1], "ascii")) r->format = F_ASCII;
            else if (is_word(w[1], wl[1], "binary_little_endian")) r->format = F_LE;
            else if (is_word(w[1], wl[1], "binary_big_endian")) r->format = F_BE;
            else return header_error(r, line, "unknown format", w[1], wl[1]);
            if (!is_word(w[2], wl[2], "1.0")) return header_error(r, line, "unsupported PLY version", w[2], wl[2]);
            have_format = 1;
            continue;
        }
        if (!have_format) return header_error(r, line, "expected the format line, got", ls, (size_t)(eol - ls));
        hv_status s;
        if (is_word(w[0], wl[0], "element")) s = header_element(r, line, w, wl, n, ls, (size_t)(eol - ls));
        else if (is_word(w[0], wl[0], "property")) s = header_property(r, line, w, wl, n, ls, (size_t)(eol - ls));
        else if (is_word(w[0], wl[0], "end_header")) {
            if (n != 1) return header_error(r, line, "expected 'end_header', got", ls, (size_t)(eol - ls));
            r->p = (const unsigned char *)p;
            r->line = line + 1;
            return roles(r);
        } else
            return header_error(r, line, "unknown header keyword", w[0], wl[0]);
        if (s != HV_OK) return s;
    }
}

static const char *plural(const ply_elem *el)
{
    return el->role == 1 ? "vertices" : el->role == 2 ? "faces" : "elements of that kind";
}

/* Counts against the bytes after the header: each element takes at least its scalars' sizes
 * and its lists' count sizes (binary), or one character and one separator per value (ASCII). */
static hv_status check_counts(const ply_reader *r)
{
    /* ASCII: the last value may end the file without a separator */
    uint64_t left = (uint64_t)(r->end - r->p) + (r->format == F_ASCII);
    for (size_t i = 0; i < r->nelems; ++i) {
        const ply_elem *el = &r->elems[i];
        uint64_t min = 0;
        for (size_t k = 0; k < el->nprops; ++k) {
            const ply_prop *pr = &el->props[k];
            int t = pr->count_type != T_NONE ? pr->count_type : pr->type;
            min += r->format == F_ASCII ? 2 : (uint64_t)k_type_size[t];
        }
        if (min == 0 || el->count == 0) continue;
        uint64_t fit = left / min;
        if (el->count > fit)
            return hv_error_set(HV_ERR_BAD_INPUT,
                                "%s: header declares %llu %s but the %llu bytes after the header hold at "
                                "most %llu",
                                r->name, (unsigned long long)el->count, plural(el),
                                (unsigned long long)(r->end - r->p), (unsigned long long)fit);
        left -= el->count * min;
    }
    return HV_OK;
}

/* ---- values ------------------------------------------------------------------------------ */

typedef union ply_value {
    int64_t i;
    double f;
} ply_value;

static const char *elem_word(const ply_elem *el) { return el->role == 1 ? "vertex" : el->role == 2 ? "face" : el->name; }

/* What a value is, for messages, put in words only when one is needed: a property, the count of
 * a list, a face's corner. */
typedef struct ply_what {
    int kind; /* 0 property `name`, 1 the count of list `name`, 2 corner `n` */
    const char *name;
    uint64_t n;
} ply_what;

static const char *what_text(const ply_what *w, char *buf, size_t cap)
{
    if (w->kind == 0) snprintf(buf, cap, "%s", w->name);
    else if (w->kind == 1) snprintf(buf, cap, "the count of list %s", w->name);
    else snprintf(buf, cap, "corner %llu", (unsigned long long)w->n);
    return buf;
}

/* Where a value is, for messages: "line 12: vertex 3" (ASCII), "vertex 3 (byte 180)" (binary). */
static const char *place(const ply_reader *r, const ply_elem *el, uint64_t index, size_t at, char *buf, size_t cap)
{
    if (r->format == F_ASCII)
        snprintf(buf, cap, "line %zu: %s %llu", r->line, elem_word(el), (unsigned long long)index);
    else
        snprintf(buf, cap, "%s %llu (byte %zu)", elem_word(el), (unsigned long long)index, at);
    return buf;
}

/* Binary: one value of type t at the cursor. */
static hv_status read_binary(ply_reader *r, int t, const ply_elem *el, uint64_t index, const ply_what *what,
                             ply_value *v)
{
    size_t n = (size_t)k_type_size[t];
    if ((size_t)(r->end - r->p) < n) {
        char pl[160], wt[96];
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: %s ends past the end of the file (truncated)", r->name,
                            place(r, el, index, (size_t)(r->p - r->d), pl, sizeof pl), what_text(what, wt, sizeof wt));
    }
    unsigned char b[8];
    if (r->format == F_LE) memcpy(b, r->p, n);
    else
        for (size_t k = 0; k < n; ++k) b[k] = r->p[n - 1 - k];
    r->p += n;
    switch (t) {
    case T_INT8: v->i = (int8_t)b[0]; break;
    case T_UINT8: v->i = b[0]; break;
    case T_INT16: { int16_t x; memcpy(&x, b, 2); v->i = x; } break;
    case T_UINT16: { uint16_t x; memcpy(&x, b, 2); v->i = x; } break;
    case T_INT32: { int32_t x; memcpy(&x, b, 4); v->i = x; } break;
    case T_UINT32: { uint32_t x; memcpy(&x, b, 4); v->i = x; } break;
    case T_FLOAT32: { float x; memcpy(&x, b, 4); v->f = x; } break;
    default: { double x; memcpy(&x, b, 8); v->f = x; } break;
    }
    return HV_OK;
}

/* ASCII: one value of type t, on the current line. */
static hv_status read_ascii(ply_reader *r, int t, const ply_elem *el, uint64_t index, const ply_what *w,
                            ply_value *v)
{
    const char *p = (const char *)r->p, *end = (const char *)r->end;
    char pl[160], q[72], wt[96];
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
    if (p == end || *p == '\n')
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: %s is missing (the line ends)", r->name,
                            place(r, el, index, 0, pl, sizeof pl), what_text(w, wt, sizeof wt));
    const char *s = p;
    while (p < end && *p != ' ' && *p != '\t' && *p != '\r' && *p != '\n') ++p;
    r->p = (const unsigned char *)p;
    char buf[80];
    size_t n = (size_t)(p - s);
    if (n >= sizeof buf) goto bad_number;
    memcpy(buf, s, n);
    buf[n] = '\0';
    char *endp;
    errno = 0;
    if (is_integer(t)) {
        long long x = strtoll(buf, &endp, 10);
        static const long long lo[] = {INT8_MIN, 0, INT16_MIN, 0, INT32_MIN, 0};
        static const long long hi[] = {INT8_MAX, UINT8_MAX, INT16_MAX, UINT16_MAX, INT32_MAX, UINT32_MAX};
        if (n == 0 || endp != buf + n) goto bad_number;
        if (errno == ERANGE || x < lo[t] || x > hi[t])
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: %s is %s, out of range for %s", r->name,
                                place(r, el, index, 0, pl, sizeof pl), what_text(w, wt, sizeof wt), buf, k_type_names[t][0]);
        v->i = x;
    } else {
        double x = strtod(buf, &endp);
        if (n == 0 || endp != buf + n) goto bad_number;
        v->f = x; /* a float32 out of range is refused where it is used, with its text's value */
    }
    return HV_OK;
bad_number:
    return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: %s is not %s: '%s'", r->name, place(r, el, index, 0, pl, sizeof pl),
                        what_text(w, wt, sizeof wt), is_integer(t) ? "an integer" : "a number", hv_quote(q, sizeof q, s, n));
}

static hv_status read_value(ply_reader *r, int t, const ply_elem *el, uint64_t index, const ply_what *what,
                            ply_value *v)
{
    return r->format == F_ASCII ? read_ascii(r, t, el, index, what, v) : read_binary(r, t, el, index, what, v);
}

/* ASCII: the end of an element's line. */
static hv_status end_line(ply_reader *r, const ply_elem *el, uint64_t index)
{
    if (r->format != F_ASCII) return HV_OK;
    const char *p = (const char *)r->p, *end = (const char *)r->end;
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
    if (p < end && *p != '\n') {
        const char *s = p;
        while (p < end && *p != '\n' && p - s < 40) ++p;
        char q[72], pl[160];
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: more values than its %zu properties: '%s'", r->name,
                            place(r, el, index, 0, pl, sizeof pl), el->nprops, hv_quote(q, sizeof q, s, (size_t)(p - s)));
    }
    if (p < end) ++p;
    r->line++;
    r->p = (const unsigned char *)p;
    return HV_OK;
}

static double as_double(int t, ply_value v) { return is_integer(t) ? (double)v.i : v.f; }

/* ---- elements ---------------------------------------------------------------------------- */

/* A face's vertex list (its count read, at byte `at`), fan-triangulated around its first corner. */
static hv_status read_face(ply_reader *r, const ply_elem *el, uint64_t f, uint64_t count, int item, size_t at)
{
    char pl[160];
    if (count < 3)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: %llu vertices, at least 3 needed", r->name,
                            place(r, el, f, at, pl, sizeof pl), (unsigned long long)count);
    uint64_t min = r->format == F_ASCII ? 2 : (uint64_t)k_type_size[item];
    uint64_t left = (uint64_t)(r->end - r->p) + (r->format == F_ASCII);
    if (count > left / min) /* a count that lies, or a truncated file */
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: declares %llu vertices but the %zu bytes left hold at most %llu",
                            r->name, place(r, el, f, at, pl, sizeof pl), (unsigned long long)count,
                            (size_t)(r->end - r->p), (unsigned long long)(left / min));
    hv_status s = hv_grow((void **)&r->tri, &r->tcap, 3 * (r->nt + count - 2), sizeof *r->tri);
    if (s != HV_OK) return s;
    uint32_t first = 0, prev = 0;
    for (uint64_t k = 0; k < count; ++k) {
        size_t vat = (size_t)(r->p - r->d);
        ply_value v;
        ply_what what = {2, NULL, k + 1};
        if ((s = read_value(r, item, el, f, &what, &v)) != HV_OK) return s;
        if (v.i < 0 || (uint64_t)v.i >= r->vertex->count)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: vertex index %lld out of range (%llu vertices)", r->name,
                                place(r, el, f, vat, pl, sizeof pl), (long long)v.i, (unsigned long long)r->vertex->count);
        uint32_t idx = (uint32_t)v.i;
        if (k == 0) first = idx;
        else if (k >= 2) { /* a fan around the first corner */
            r->tri[3 * r->nt] = first;
            r->tri[3 * r->nt + 1] = prev;
            r->tri[3 * r->nt + 2] = idx;
            r->nt++;
        }
        prev = idx;
    }
    return HV_OK;
}

static hv_status read_element(ply_reader *r, const ply_elem *el)
{
    static const char *const axis[] = {"x", "y", "z"};
    if (el->nprops == 0) return HV_OK; /* no data, whatever its count */
    char pl[160];
    for (uint64_t i = 0; i < el->count; ++i) {
        for (size_t k = 0; k < el->nprops; ++k) {
            const ply_prop *pr = &el->props[k];
            ply_value v;
            size_t at = (size_t)(r->p - r->d);
            hv_status s;
            if (pr->count_type == T_NONE) {
                ply_what what = {0, pr->name, 0};
                if ((s = read_value(r, pr->type, el, i, &what, &v)) != HV_OK) return s;
                if (el->role != 1) continue;
                for (int c = 0; c < 4 && r->colour; ++c) {
                    if (el->rgba[c] != (int)k) continue;
                    static const char *const chan[] = {"red", "green", "blue", "alpha"};
                    double x = as_double(pr->type, v);
                    if (pr->type != T_UINT8) {
                        if (!(x >= 0 && x <= 1))
                            return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: %s %g outside [0, 1]", r->name,
                                                place(r, el, i, at, pl, sizeof pl), chan[c], x);
                        x = floor(x * 255 + 0.5);
                    }
                    int sh = 24 - 8 * c;
                    r->colour[i] = (r->colour[i] & ~(0xFFu << sh)) | (uint32_t)x << sh;
                }
                for (int a = 0; a < 3; ++a) {
                    if (el->xyz[a] != (int)k) continue;
                    double x = as_double(pr->type, v);
                    float fx = (float)x;
                    if (!isfinite(fx))
                        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: %s is not a finite float (%g)", r->name,
                                            place(r, el, i, at, pl, sizeof pl), axis[a], x);
                    r->xyz[3 * i + (uint64_t)a] = fx;
                }
                continue;
            }
            ply_what what = {1, pr->name, 0};
            if ((s = read_value(r, pr->count_type, el, i, &what, &v)) != HV_OK) return s;
            if (v.i < 0)
                return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: list %s has a negative count (%lld)", r->name,
                                    place(r, el, i, at, pl, sizeof pl), pr->name, (long long)v.i);
            uint64_t count = (uint64_t)v.i;
            if (el->role == 2 && el->indices == (int)k) {
                if ((s = read_face(r, el, i, count, pr->type, at)) != HV_OK) return s;
                continue;
            }
            if (r->format != F_ASCII) { /* skipped by its size */
                uint64_t bytes = count * (uint64_t)k_type_size[pr->type];
                if (bytes > (uint64_t)(r->end - r->p))
                    return hv_error_set(HV_ERR_BAD_INPUT,
                                        "%s: %s: list %s of %llu items ends past the end of the file (truncated)",
                                        r->name, place(r, el, i, at, pl, sizeof pl), pr->name, (unsigned long long)count);
                r->p += bytes;
                continue;
            }
            ply_what item = {0, pr->name, 0};
            for (uint64_t k2 = 0; k2 < count; ++k2)
                if ((s = read_value(r, pr->type, el, i, &item, &v)) != HV_OK) return s;
        }
        hv_status s = end_line(r, el, i);
        if (s != HV_OK) return s;
    }
    return HV_OK;
}

hv_status hv_mesh_parse_ply(const void *data, size_t size, const char *name, hv_mesh **out)
{
    *out = NULL;
    if (size == 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: empty file (0 bytes)", name);
    ply_reader r;
    memset(&r, 0, sizeof r);
    r.name = name;
    r.d = data;
    r.end = r.d + size;
    float *soup = NULL;
    hv_status s = parse_header(&r);
    if (s == HV_OK) s = check_counts(&r);
    if (s == HV_OK && r.vertex->count > UINT32_MAX)
        s = hv_error_set(HV_ERR_LIMIT, "%s: header declares %llu vertices, more than %u", name,
                         (unsigned long long)r.vertex->count, UINT32_MAX);
    if (s == HV_OK && r.vertex->count &&
        !(r.xyz = hv_malloc_array((size_t)r.vertex->count, 3 * sizeof(float))))
        s = HV_ERR_NOMEM;
    if (s == HV_OK && r.vertex->count && r.vertex->rgba[0] >= 0) {
        if (!(r.colour = hv_malloc_array((size_t)r.vertex->count, sizeof *r.colour))) s = HV_ERR_NOMEM;
        for (size_t i = 0; s == HV_OK && i < r.vertex->count; ++i) r.colour[i] = 0xFFu; /* opaque */
    }
    for (size_t i = 0; i < r.nelems && s == HV_OK; ++i) s = read_element(&r, &r.elems[i]);
    if (s == HV_OK && r.format == F_ASCII) { /* nothing but blanks after the last element */
        const unsigned char *p = r.p;
        while (p < r.end && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')) {
            if (*p == '\n') r.line++;
            ++p;
        }
        if (p < r.end)
            s = hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: data after the last element", name, r.line);
    } else if (s == HV_OK && r.p < r.end) {
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: %zu bytes of trailing data after the last element (byte %zu)", name,
                         (size_t)(r.end - r.p), (size_t)(r.p - r.d));
    }
    if (s == HV_OK && r.nt == 0) s = hv_error_set(HV_ERR_BAD_INPUT, "%s: contains no faces", name);
    if (s == HV_OK && !(soup = hv_malloc_array(r.nt, 9 * sizeof(float)))) s = HV_ERR_NOMEM;
    if (s == HV_OK) {
        for (size_t t = 0; t < r.nt; ++t)
            for (int c = 0; c < 3; ++c)
                memcpy(soup + 9 * t + 3 * c, r.xyz + 3 * (size_t)r.tri[3 * t + (size_t)c], 3 * sizeof(float));
        hv_mesh_format f = r.format == F_ASCII ? HV_MESH_PLY_ASCII : r.format == F_LE ? HV_MESH_PLY_BINARY_LE
                                                                                      : HV_MESH_PLY_BINARY_BE;
        s = hv_mesh_build(soup, r.nt, name, f, NULL, 0, NULL, 0, NULL, out);
    }
    if (s == HV_OK && r.colour) { /* facets are in file order: corner c of facet t is vertex tri[3t+c] */
        s = hv_io_vertex_colours(*out, r.colour, r.tri, r.nt, NULL);
        if (s != HV_OK) {
            hv_mesh_destroy(*out);
            *out = NULL;
        }
    }
    for (size_t i = 0; i < r.nelems; ++i) free(r.elems[i].props);
    free(r.xyz);
    free(r.colour);
    free(r.tri);
    free(soup);
    return s;
}
