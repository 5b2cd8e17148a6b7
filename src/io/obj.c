/* src/io/obj.c - Wavefront OBJ input: vertices, polygon faces (fan-triangulated), `o`/`g`
 * groups as bodies, `usemtl` names as materials, and (read from files) the `mtllib` libraries'
 * colours (Kd, d) and diffuse textures (map_Kd, sampled at the `vt` coordinates). A strict
 * reader for hostile input: every index is checked against the vertices defined above it, every
 * coordinate must be a finite float, and every defect is one message naming the file, the line
 * and the value. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/internal.h"
#include "hovox/image.h"
#include "io_internal.h"

#define NO_VT UINT32_MAX


typedef struct obj_reader {
    const char *name;
    size_t line; /* where the statement being read starts */
    float *xyz;  /* 3 per vertex */
    size_t nv, vcap;
    size_t nvn;      /* counted for the index checks; their values are not used */
    float *vt;       /* 2 per texture coordinate (u, v) */
    size_t nvt, vtcap;
    uint32_t *tvt;   /* 3 per triangle: texture coordinate indices, or NO_VT */
    size_t tvtcap;
    uint32_t *poly_vt;
    size_t pvcap;
    hv_buf mtllibs;  /* the mtllib statements' rest of line, each NUL-ended, in order */
    size_t *mtllib_line;
    size_t nmtllib, mlcap;
    uint32_t *tri;   /* 3 per triangle, file order */
    int32_t *tbody, *tmat;
    size_t nt, tcap, bcap, mcap;
    hv_names bodies, mats;
    int32_t body, mat;      /* current body and material (-1: none) */
    int body_new, mat_new;  /* an o/g or usemtl since the last face: look the name up there */
    hv_buf body_name, mat_name;
    size_t ignored;         /* l and p statements */
    uint32_t *vrgb;         /* per vertex 0xRRGGBBAA from `v x y z r g b` (0: none); NULL while none has one */
    size_t vrcap, ncol;     /* vertices with a colour */
    size_t bad_col_line;    /* the first colour outside [0, 1] (0: none) */
    char bad_col[32];
    uint32_t *poly;
    size_t pcap;
} obj_reader;


/* The rest of the statement, trimmed, a comment cut off: a name (o, g, usemtl). */
static void rest_of(const char *p, const char *e, const char **rs, const char **re)
{
    while (p < e && hv_io_blank(*p)) ++p;
    const char *q = p;
    while (q < e && !(*q == '#' && (q == p || hv_io_blank(q[-1])))) ++q;
    while (q > p && hv_io_blank(q[-1])) --q;
    *rs = p;
    *re = q;
}

/* "vertex y is not a number: '1x'" */
static hv_status bad_coord(const obj_reader *r, const char *what, const char *problem, const char *s, size_t n)
{
    char q[72];
    return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: vertex %s is not a %s: '%s'", r->name, r->line, what,
                        problem, hv_quote(q, sizeof q, s, n));
}

static hv_status parse_coord(const obj_reader *r, const char *s, const char *e, const char *what, float *out)
{
    size_t n = (size_t)(e - s);
    float v = 0;
    /* strtof's value and verdict, without its cost on plain decimals (hv_parse_float) */
    if (n >= 80 || !hv_parse_float(s, n, &v)) return bad_coord(r, what, "number", s, n);
    if (!isfinite(v)) return bad_coord(r, what, "finite float", s, n);
    *out = v;
    return HV_OK;
}

/* vt u [v [w]]: v defaults to 0, w is read and not used. */
static hv_status tex_coord(obj_reader *r, const char *p, const char *e)
{
    static const char *const what[] = {"u", "v", "w"};
    hv_status s = hv_grow((void **)&r->vt, &r->vtcap, 2 * (r->nvt + 1), sizeof *r->vt);
    if (s != HV_OK) return s;
    if (r->nvt >= UINT32_MAX - 1)
        return hv_error_set(HV_ERR_LIMIT, "%s: line %zu: more than %u texture coordinates", r->name, r->line,
                            UINT32_MAX - 1);
    const char *ts, *te;
    int k = 0;
    float uv[3] = {0, 0, 0};
    for (; hv_io_next_token(&p, e, &ts, &te); ++k) {
        if (k == 3)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: texture coordinate has more than 3 values (u v w)",
                                r->name, r->line);
        char q[72];
        size_t n = (size_t)(te - ts);
        float v = NAN;
        if (n >= 80 || !hv_parse_float(ts, n, &v) || !isfinite(v))
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: texture coordinate %s is not a finite number: '%s'",
                                r->name, r->line, what[k], hv_quote(q, sizeof q, ts, n));
        uv[k] = v;
    }
    if (k == 0)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: texture coordinate has no values", r->name, r->line);
    r->vt[2 * r->nvt] = uv[0];
    r->vt[2 * r->nvt + 1] = uv[1];
    r->nvt++;
    return HV_OK;
}

/* `v x y z r g b`, as MeshLab, Blender and scanners write a vertex's colour (sRGB in [0, 1]; a w
 * or seven values carry none): vertex r->nv's colour, 0 without one. */
static hv_status vertex_colour(obj_reader *r, const float *rgb)
{
    int first = !r->vrgb; /* the first colour: the vertices above it have none */
    hv_status s = hv_grow((void **)&r->vrgb, &r->vrcap, r->nv + 1, sizeof *r->vrgb);
    if (s != HV_OK) return s;
    if (first) memset(r->vrgb, 0, r->nv * sizeof *r->vrgb);
    uint32_t c = 0xFFu;
    for (int k = 0; rgb && k < 3; ++k) {
        if (!(rgb[k] >= 0 && rgb[k] <= 1)) {
            if (!r->bad_col_line) {
                r->bad_col_line = r->line;
                snprintf(r->bad_col, sizeof r->bad_col, "%g", (double)rgb[k]);
            }
            rgb = NULL;
            break;
        }
        c |= (uint32_t)lrintf(rgb[k] * 255) << (24 - 8 * k);
    }
    r->vrgb[r->nv] = rgb ? c : 0;
    r->ncol += rgb != NULL;
    return HV_OK;
}

static hv_status vertex(obj_reader *r, const char *p, const char *e)
{
    static const char *const what[] = {"x", "y", "z", "w", "value 5", "value 6", "value 7"};
    hv_status s = hv_grow((void **)&r->xyz, &r->vcap, 3 * (r->nv + 1), sizeof *r->xyz);
    if (s != HV_OK) return s;
    if (r->nv >= UINT32_MAX)
        return hv_error_set(HV_ERR_LIMIT, "%s: line %zu: more than %u vertices", r->name, r->line, UINT32_MAX);
    const char *ts, *te;
    int k = 0;
    float val[7];
    for (; hv_io_next_token(&p, e, &ts, &te); ++k) {
        if (k == 7)
            return hv_error_set(HV_ERR_BAD_INPUT,
                                "%s: line %zu: vertex has more than 7 values (x y z [w], or x y z and a "
                                "colour)",
                                r->name, r->line);
        float v = 0;
        if ((s = parse_coord(r, ts, te, what[k], &v)) != HV_OK) return s;
        if (k < 3) r->xyz[3 * r->nv + (size_t)k] = v;
        val[k] = v;
    }
    if (k < 3)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: vertex has %d coordinate%s, 3 needed", r->name,
                            r->line, k, k == 1 ? "" : "s");
    if ((k == 6 || r->vrgb) && (s = vertex_colour(r, k == 6 ? val + 3 : NULL)) != HV_OK) return s;
    r->nv++;
    return HV_OK;
}

/* An OBJ reference number: a nonzero integer, counted from 1 or, negative, back from the last
 * element defined so far. Elements defined below the face are out of range: the OBJ
 * specification numbers elements in the order they are defined, and a face names them. */
static hv_status resolve(const obj_reader *r, size_t corner, const char *s, size_t n, size_t count,
                         const char *what, uint32_t *out)
{
    int neg = n > 0 && s[0] == '-';
    size_t i = (size_t)neg || (n > 0 && s[0] == '+');
    uint64_t v = 0;
    int over = 0;
    if (i == n) goto bad_number;
    for (; i < n; ++i) {
        if (s[i] < '0' || s[i] > '9') goto bad_number;
        if (v > (UINT64_MAX - 9) / 10) over = 1;
        else v = v * 10 + (uint64_t)(s[i] - '0');
    }
    char q[72];
    if (v == 0 && !over)
        return hv_error_set(HV_ERR_BAD_INPUT,
                            "%s: line %zu: face vertex %zu: %s index 0 (indices count from 1, or "
                            "back from -1)",
                            r->name, r->line, corner, what);
    if (over || v > count)
        return hv_error_set(HV_ERR_BAD_INPUT,
                            "%s: line %zu: face vertex %zu: %s index %s out of range (%zu defined "
                            "above the face)",
                            r->name, r->line, corner, what, hv_quote(q, sizeof q, s, n), count);
    *out = (uint32_t)(neg ? count - v : v - 1);
    return HV_OK;
bad_number:
    return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: face vertex %zu: bad %s index '%s'", r->name,
                        r->line, corner, what, hv_quote(q, sizeof q, s, n));
}

/* One corner of a face: v, v/vt, v//vn or v/vt/vn; *vt is NO_VT without a texture coordinate. */
static hv_status corner_ref(const obj_reader *r, size_t corner, const char *s, const char *e, uint32_t *v,
                            uint32_t *vt)
{
    *vt = NO_VT;
    const char *a = memchr(s, '/', (size_t)(e - s));
    const char *ve = a ? a : e;
    hv_status st = resolve(r, corner, s, (size_t)(ve - s), r->nv, "vertex", v);
    if (st != HV_OK || !a) return st;
    const char *b = memchr(a + 1, '/', (size_t)(e - a - 1));
    uint32_t ignored;
    if (b != a + 1 && (st = resolve(r, corner, a + 1, (size_t)((b ? b : e) - a - 1), r->nvt,
                                    "texture coordinate", vt)) != HV_OK)
        return st;
    if (b && (st = resolve(r, corner, b + 1, (size_t)(e - b - 1), r->nvn, "normal", &ignored)) != HV_OK)
        return st;
    return HV_OK;
}

/* The body and material a face goes to: names given since the last face are looked up now, so
 * groups and materials that hold no face are not there. */
static hv_status face_owner(obj_reader *r)
{
    hv_status s;
    if (r->body < 0 || r->body_new) {
        if (!r->body_new) { /* facets before any o or g: a body named after the file */
            char *stem = hv_file_stem(r->name);
            if (!stem) return HV_ERR_NOMEM;
            s = hv_names_intern(&r->bodies, stem, strlen(stem), &r->body);
            free(stem);
        } else {
            s = hv_names_intern(&r->bodies, r->body_name.data ? r->body_name.data : "", r->body_name.len,
                                &r->body);
        }
        if (s != HV_OK) return s;
        r->body_new = 0;
    }
    if (r->mat_new) {
        r->mat = -1;
        if (r->mat_name.len &&
            (s = hv_names_intern(&r->mats, r->mat_name.data, r->mat_name.len, &r->mat)) != HV_OK)
            return s;
        r->mat_new = 0;
    }
    return HV_OK;
}

static hv_status face(obj_reader *r, const char *p, const char *e)
{
    const char *ts, *te;
    size_t n = 0;
    hv_status s;
    while (hv_io_next_token(&p, e, &ts, &te)) {
        if ((s = hv_grow((void **)&r->poly, &r->pcap, n + 1, sizeof *r->poly)) != HV_OK ||
            (s = hv_grow((void **)&r->poly_vt, &r->pvcap, n + 1, sizeof *r->poly_vt)) != HV_OK)
            return s;
        if ((s = corner_ref(r, n + 1, ts, te, &r->poly[n], &r->poly_vt[n])) != HV_OK) return s;
        ++n;
    }
    if (n < 3)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: face has %zu vertices, at least 3 needed", r->name,
                            r->line, n);
    if ((s = face_owner(r)) != HV_OK) return s;
    size_t add = n - 2; /* a fan around the first corner */
    if ((s = hv_grow((void **)&r->tri, &r->tcap, 3 * (r->nt + add), sizeof *r->tri)) != HV_OK ||
        (s = hv_grow((void **)&r->tbody, &r->bcap, r->nt + add, sizeof *r->tbody)) != HV_OK ||
        (s = hv_grow((void **)&r->tmat, &r->mcap, r->nt + add, sizeof *r->tmat)) != HV_OK ||
        (s = hv_grow((void **)&r->tvt, &r->tvtcap, 3 * (r->nt + add), sizeof *r->tvt)) != HV_OK)
        return s;
    int all_vt = 1; /* a face textures only when every corner has a coordinate */
    for (size_t k = 0; k < n; ++k) all_vt &= r->poly_vt[k] != NO_VT;
    for (size_t k = 1; k + 1 < n; ++k, ++r->nt) {
        r->tri[3 * r->nt] = r->poly[0];
        r->tri[3 * r->nt + 1] = r->poly[k];
        r->tri[3 * r->nt + 2] = r->poly[k + 1];
        r->tvt[3 * r->nt] = all_vt ? r->poly_vt[0] : NO_VT;
        r->tvt[3 * r->nt + 1] = all_vt ? r->poly_vt[k] : NO_VT;
        r->tvt[3 * r->nt + 2] = all_vt ? r->poly_vt[k + 1] : NO_VT;
        r->tbody[r->nt] = r->body;
        r->tmat[r->nt] = r->mat;
    }
    return HV_OK;
}

static int word_is(const char *s, const char *e, const char *w)
{
    size_t n = strlen(w);
    return (size_t)(e - s) == n && memcmp(s, w, n) == 0;
}

static int word_in(const char *s, const char *e, const char *const *list)
{
    for (; *list; ++list)
        if (word_is(s, e, *list)) return 1;
    return 0;
}

static hv_status statement(obj_reader *r, const char *p, const char *e)
{
    static const char *const ignored[] = {"s", "mg", "maplib", "usemap", "lod", "bevel", "c_interp",
                                          "d_interp", "shadow_obj", "trace_obj", "ctech", "stech", NULL};
    static const char *const freeform[] = {"vp", "cstype", "deg", "bmat", "step", "curv", "curv2", "surf",
                                           "parm", "trim", "hole", "scrv", "sp", "end", "con", NULL};
    const char *ks, *ke;
    if (!hv_io_next_token(&p, e, &ks, &ke)) return HV_OK; /* blank or comment */
    if (word_is(ks, ke, "v")) return vertex(r, p, e);
    if (word_is(ks, ke, "f")) return face(r, p, e);
    if (word_is(ks, ke, "vt")) return tex_coord(r, p, e);
    if (word_is(ks, ke, "vn")) return r->nvn++, HV_OK;
    const char *ns, *ne;
    if (word_is(ks, ke, "o") || word_is(ks, ke, "g")) {
        rest_of(p, e, &ns, &ne);
        r->body_name.len = 0;
        hv_buf_append(&r->body_name, ns, (size_t)(ne - ns));
        r->body_new = 1;
        return r->body_name.failed ? HV_ERR_NOMEM : HV_OK;
    }
    if (word_is(ks, ke, "mtllib")) {
        rest_of(p, e, &ns, &ne);
        hv_status s = hv_grow((void **)&r->mtllib_line, &r->mlcap, r->nmtllib + 1, sizeof *r->mtllib_line);
        if (s != HV_OK) return s;
        r->mtllib_line[r->nmtllib++] = r->line;
        hv_buf_append(&r->mtllibs, ns, (size_t)(ne - ns));
        hv_buf_append(&r->mtllibs, "", 1);
        return r->mtllibs.failed ? HV_ERR_NOMEM : HV_OK;
    }
    if (word_is(ks, ke, "usemtl")) {
        rest_of(p, e, &ns, &ne);
        r->mat_name.len = 0;
        hv_buf_append(&r->mat_name, ns, (size_t)(ne - ns));
        r->mat_new = 1;
        return r->mat_name.failed ? HV_ERR_NOMEM : HV_OK;
    }
    if (word_is(ks, ke, "l") || word_is(ks, ke, "p")) return r->ignored++, HV_OK;
    if (word_in(ks, ke, ignored)) return HV_OK;
    char q[72];
    if (word_in(ks, ke, freeform))
        return hv_error_set(HV_ERR_BAD_INPUT,
                            "%s: line %zu: '%s': free-form curves and surfaces are not supported (polygon "
                            "faces only)",
                            r->name, r->line, hv_quote(q, sizeof q, ks, (size_t)(ke - ks)));
    return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: unknown statement '%s'", r->name, r->line,
                        hv_quote(q, sizeof q, ks, (size_t)(ke - ks)));
}

/* End of the line [s, e) without trailing blanks; 1 when it ends in a continuation '\'. */
static int continued(const char *s, const char *e)
{
    while (e > s && hv_io_blank(e[-1])) --e;
    return e > s && e[-1] == '\\';
}

/* "dir/" of a path (empty for a bare name), into b. */
static void dir_of(hv_buf *b, const char *path)
{
    const char *slash = strrchr(path, '/');
    b->len = 0;
    if (slash) hv_buf_append(b, path, (size_t)(slash - path) + 1);
    else hv_buf_append(b, "", 0);
}

/* A file named in `from` (a path), relative to from's directory unless absolute, into b. */
static void beside(hv_buf *b, const char *from, const char *file)
{
    if (file[0] == '/') {
        b->len = 0;
        hv_buf_puts(b, file);
        return;
    }
    dir_of(b, from);
    hv_buf_puts(b, file);
}

/* The libraries of every mtllib statement, read beside the OBJ file: the whole rest of the line
 * names one file when it exists (names with blanks), else each word names one. */
static hv_status read_mtllibs(obj_reader *r, hv_mtl *lib)
{
    hv_buf path;
    hv_buf_init(&path);
    hv_status s = HV_OK;
    const char *names = r->mtllibs.data;
    for (size_t i = 0; i < r->nmtllib && s == HV_OK; ++i) {
        const char *rest = names;
        names += strlen(names) + 1;
        if (!*rest)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: mtllib names no file", r->name, r->mtllib_line[i]);
        beside(&path, r->name, rest);
        int whole = !path.failed && access(path.data, F_OK) == 0;
        const char *p = rest, *e = rest + strlen(rest), *ts, *te;
        while (s == HV_OK && (whole ? p < e : hv_io_next_token(&p, e, &ts, &te))) {
            if (whole) {
                ts = p;
                te = p = e;
            }
            char *file = hv_malloc((size_t)(te - ts) + 1);
            if (!file) {
                s = HV_ERR_NOMEM;
                break;
            }
            memcpy(file, ts, (size_t)(te - ts));
            file[te - ts] = '\0';
            beside(&path, r->name, file);
            free(file);
            if (path.failed) {
                s = HV_ERR_NOMEM;
                break;
            }
            /* a library that is not there (OBJ files travel without theirs) leaves the materials
             * names only, as an OBJ read from memory has them */
            if (access(path.data, F_OK) != 0) continue;
            char *data = NULL;
            size_t size = 0;
            s = hv_read_file(path.data, (size_t)64 << 20, &data, &size);
            if (s == HV_ERR_IO || s == HV_ERR_LIMIT) {
                char why[512];
                snprintf(why, sizeof why, "%s", hv_last_error());
                s = hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: material library %s", r->name,
                                 r->mtllib_line[i], why);
            }
            if (s == HV_OK) {
                hv_input_note(path.data);
                s = hv_mtl_parse(data, size, path.data, lib);
            }
            free(data);
        }
    }
    hv_buf_free(&path);
    return s;
}

/* The picture of a map_Kd, read beside its library. */
static hv_status read_texture(const hv_mtl_material *m, const char *lib_path, hv_rgba8 *img)
{
    hv_buf path;
    hv_buf_init(&path);
    beside(&path, lib_path, m->map);
    if (path.failed) return HV_ERR_NOMEM;
    char *data = NULL;
    size_t size = 0;
    char why[512];
    hv_status s = hv_read_file(path.data, (size_t)1 << 30, &data, &size);
    if (s == HV_OK) {
        hv_input_note(path.data);
        s = hv_rgba8_decode(data, size, path.data, (uint64_t)1 << 28, img);
    }
    if (s == HV_ERR_IO || s == HV_ERR_BAD_INPUT || s == HV_ERR_LIMIT) {
        snprintf(why, sizeof why, "%s", hv_last_error());
        s = hv_error_set(s == HV_ERR_LIMIT ? HV_ERR_LIMIT : HV_ERR_BAD_INPUT, "%s: line %zu: map_Kd: %s", lib_path,
                         m->map_line, why);
    }
    free(data);
    hv_buf_free(&path);
    return s;
}

/* The look of an OBJ's materials. */
typedef struct obj_look {
    hv_mtl lib;
    int32_t *tex_of;   /* per OBJ material: its texture index, or -1 */
    hv_rgba8 *pics;    /* the textures, in order */
    char **pic_names;  /* map_Kd as written */
    const hv_mtl_material **pic_mat; /* the first material of each texture */
    const hv_mtl_material **mtl_of;  /* per OBJ material: its definition, or NULL */
    size_t npics;
} obj_look;

static void look_free(obj_look *L)
{
    hv_mtl_free(&L->lib);
    free(L->tex_of);
    for (size_t i = 0; i < L->npics; ++i) hv_rgba8_free(&L->pics[i]);
    free(L->pics);
    free(L->pic_names);
    free(L->pic_mat);
    free(L->mtl_of);
}

static uint8_t unit8(float v) { return (uint8_t)lrintf(v * 255.0f); }

/* The look of the materials used: colours into mats, textures loaded (one per distinct map). */
static hv_status look_up(obj_reader *r, hv_mesh_material *mats, size_t nm, obj_look *L)
{
    hv_status s = read_mtllibs(r, &L->lib);
    if (s != HV_OK) return s;
    L->tex_of = hv_malloc_array(nm ? nm : 1, sizeof *L->tex_of);
    L->pics = hv_calloc(nm ? nm : 1, sizeof *L->pics);
    L->pic_names = hv_calloc(nm ? nm : 1, sizeof *L->pic_names);
    L->pic_mat = hv_calloc(nm ? nm : 1, sizeof *L->pic_mat);
    L->mtl_of = hv_calloc(nm ? nm : 1, sizeof *L->mtl_of);
    if (!L->tex_of || !L->pics || !L->pic_names || !L->pic_mat || !L->mtl_of) return HV_ERR_NOMEM;
    for (size_t k = 0; k < nm; ++k) {
        L->tex_of[k] = -1;
        const hv_mtl_material *m = hv_mtl_find(&L->lib, mats[k].name);
        L->mtl_of[k] = m;
        if (!m) continue;
        if (m->has_kd) {
            mats[k].rgba = (uint32_t)unit8(m->kd[0]) << 24 | (uint32_t)unit8(m->kd[1]) << 16 |
                           (uint32_t)unit8(m->kd[2]) << 8 | unit8(m->alpha);
            mats[k].has_color = 1;
        }
        if (!m->map) continue;
        for (size_t j = 0; j < L->npics && L->tex_of[k] < 0; ++j) /* the same picture, read once */
            if (strcmp(L->pic_names[j], m->map) == 0 && L->pic_mat[j]->tile == m->tile &&
                strcmp(L->pic_mat[j]->lib_path, m->lib_path) == 0)
                L->tex_of[k] = (int32_t)j;
        if (L->tex_of[k] >= 0) continue;
        if ((s = read_texture(m, m->lib_path, &L->pics[L->npics])) != HV_OK) return s;
        L->pic_names[L->npics] = m->map;
        L->pic_mat[L->npics] = m;
        L->tex_of[k] = (int32_t)L->npics++;
    }
    return HV_OK;
}

/* The vertices' colours as the corner colours of the facets (where[t]: triangle t's facet), when
 * every vertex has one in [0, 1]; else none, and a note says why. */
static hv_status vertex_colours(const obj_reader *r, const size_t *where, hv_mesh *m)
{
    char note[512];
    if (r->bad_col_line)
        snprintf(note, sizeof note, "%s: line %zu: vertex colour %s is outside [0, 1]: the vertex colours are not used",
                 r->name, r->bad_col_line, r->bad_col);
    else if (r->ncol < r->nv)
        snprintf(note, sizeof note, "%s: %zu of the %zu vertices have a colour (v x y z r g b): the vertex colours are not used",
                 r->name, r->ncol, r->nv);
    else
        return hv_io_vertex_colours(m, r->vrgb, r->tri, r->nt, where);
    return hv_mesh_add_note(m, note);
}

/* The triangles grouped by body (first appearance order), as a soup, with their materials; with
 * read_files, the materials' colours and textures from the mtllib files. */
static hv_status finish(obj_reader *r, int read_files, hv_mesh **out)
{
    size_t nb = r->bodies.n, nm = r->mats.n;
    float *soup = hv_malloc_array(r->nt, 9 * sizeof(float));
    int32_t *fmat = nm ? hv_malloc_array(r->nt, sizeof *fmat) : NULL;
    size_t *at = hv_calloc(nb + 1, sizeof *at);
    size_t *where = hv_malloc_array(r->nt, sizeof *where); /* triangle -> facet */
    hv_mesh_body *bodies = hv_calloc(nb, sizeof *bodies);
    hv_mesh_material *mats = nm ? hv_calloc(nm, sizeof *mats) : NULL;
    obj_look look;
    memset(&look, 0, sizeof look);
    float *uv = NULL;
    int32_t *ftex = NULL;
    hv_status s = HV_OK;
    if (!soup || (nm && (!fmat || !mats)) || !at || !where || !bodies) {
        s = HV_ERR_NOMEM;
        goto done;
    }
    for (size_t t = 0; t < r->nt; ++t) at[r->tbody[t] + 1]++;
    for (size_t b = 0; b < nb; ++b) {
        bodies[b].name = r->bodies.names[b];
        bodies[b].material = HV_MESH_NO_MATERIAL; /* the majority of its facets */
        bodies[b].facet_count = at[b + 1];
        at[b + 1] += at[b];
    }
    for (size_t k = 0; k < nm; ++k) mats[k].name = r->mats.names[k];
    if (read_files && r->nmtllib && (s = look_up(r, mats, nm, &look)) != HV_OK) goto done;
    for (size_t t = 0; t < r->nt; ++t) {
        size_t f = at[r->tbody[t]]++;
        where[t] = f;
        for (int c = 0; c < 3; ++c) memcpy(soup + 9 * f + 3 * c, r->xyz + 3 * (size_t)r->tri[3 * t + (size_t)c], 3 * sizeof(float));
        if (fmat) fmat[f] = r->tmat[t];
    }
    s = hv_mesh_build(soup, r->nt, r->name, HV_MESH_OBJ, bodies, nb, mats, nm, fmat, out);
    if (s == HV_OK && (r->vrgb || r->bad_col_line)) s = vertex_colours(r, where, *out);
    if (s != HV_OK || look.npics == 0) goto done;
    for (size_t j = 0; j < look.npics && s == HV_OK; ++j) {
        const hv_mtl_material *m = look.pic_mat[j];
        s = hv_mesh_add_texture(*out, look.pic_names[j], look.pics[j].rgba, (uint32_t)look.pics[j].width,
                                (uint32_t)look.pics[j].height, m->tile, m->tile, HV_FILTER_AUTO, NULL);
        if (s == HV_OK && look.pics[j].icc) /* its colours' space (painting converts through it) */
            s = hv_mesh_texture_set_icc(*out, hv_mesh_texture_count(*out) - 1, look.pics[j].icc, look.pics[j].icc_size);
    }
    uv = hv_calloc(r->nt, 6 * sizeof *uv);
    ftex = hv_malloc_array(r->nt, sizeof *ftex);
    if (s == HV_OK && (!uv || !ftex)) s = HV_ERR_NOMEM;
    for (size_t t = 0; s == HV_OK && t < r->nt; ++t) {
        size_t f = where[t];
        int32_t k = r->tmat[t], tex = k >= 0 ? look.tex_of[k] : -1;
        ftex[f] = tex >= 0 && r->tvt[3 * t] != NO_VT ? tex : -1;
        if (ftex[f] < 0) continue;
        const hv_mtl_material *m = look.mtl_of[k];
        for (int c = 0; c < 3; ++c) {
            const float *q = r->vt + 2 * (size_t)r->tvt[3 * t + (size_t)c];
            uv[6 * f + 2 * (size_t)c] = q[0] * m->scale[0] + m->offset[0];
            uv[6 * f + 2 * (size_t)c + 1] = q[1] * m->scale[1] + m->offset[1];
        }
    }
    if (s == HV_OK) s = hv_mesh_set_corner_uvs(*out, uv, ftex);
    if (s != HV_OK) {
        hv_mesh_destroy(*out);
        *out = NULL;
    }
done:
    look_free(&look);
    free(uv);
    free(ftex);
    free(soup);
    free(fmat);
    free(at);
    free(where);
    free(bodies);
    free(mats);
    return s;
}

hv_status hv_mesh_parse_obj(const void *data, size_t size, const char *name, hv_mesh **out)
{
    return hv_obj_parse(data, size, name, 0, out);
}

hv_status hv_obj_parse(const void *data, size_t size, const char *name, int read_files, hv_mesh **out)
{
    *out = NULL;
    if (size == 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: empty file (0 bytes)", name);
    obj_reader r;
    memset(&r, 0, sizeof r);
    r.name = name;
    r.body = r.mat = -1;
    hv_names_init(&r.bodies);
    hv_names_init(&r.mats);
    hv_buf_init(&r.body_name);
    hv_buf_init(&r.mat_name);
    hv_buf_init(&r.mtllibs);
    hv_buf joined;
    hv_buf_init(&joined);
    const char *p = data, *end = p + size;
    size_t line = 1;
    hv_status s = HV_OK;
    if (size >= 3 && memcmp(p, "\xEF\xBB\xBF", 3) == 0) p += 3;
    while (p < end && s == HV_OK) {
        r.line = line;
        const char *eol = memchr(p, '\n', (size_t)(end - p));
        const char *ls = p, *le = eol ? eol : end;
        p = eol ? eol + 1 : end;
        ++line;
        if (continued(ls, le)) { /* join the lines, each '\' becoming a blank */
            joined.len = 0;
            for (;;) {
                const char *bs = le;
                while (bs > ls && hv_io_blank(bs[-1])) --bs;
                hv_buf_append(&joined, ls, (size_t)(bs - 1 - ls));
                hv_buf_append(&joined, " ", 1);
                if (p >= end) break;
                eol = memchr(p, '\n', (size_t)(end - p));
                ls = p;
                le = eol ? eol : end;
                p = eol ? eol + 1 : end;
                ++line;
                if (!continued(ls, le)) {
                    hv_buf_append(&joined, ls, (size_t)(le - ls));
                    break;
                }
            }
            if (joined.failed) {
                s = HV_ERR_NOMEM;
                break;
            }
            ls = joined.data;
            le = joined.data + joined.len;
        }
        s = statement(&r, ls, le);
    }
    if (s == HV_OK && r.nt == 0)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: contains no faces (%zu vert%s%s)", name, r.nv,
                         r.nv == 1 ? "ex" : "ices", r.ignored ? "; lines and points are not read" : "");
    if (s == HV_OK) s = finish(&r, read_files, out);
    free(r.xyz);
    free(r.vrgb);
    free(r.tri);
    free(r.tbody);
    free(r.tmat);
    free(r.poly);
    free(r.poly_vt);
    free(r.vt);
    free(r.tvt);
    free(r.mtllib_line);
    hv_buf_free(&r.mtllibs);
    hv_names_free(&r.bodies);
    hv_names_free(&r.mats);
    hv_buf_free(&r.body_name);
    hv_buf_free(&r.mat_name);
    hv_buf_free(&joined);
    return s;
}

/* ---- output ------------------------------------------------------------------------------ */

/* A name on one OBJ line: control characters (a newline would end the statement) become '_'. */
static void put_name(FILE *fp, const char *s)
{
    for (; *s; ++s) fputc((unsigned char)*s < 0x20 || *s == 0x7f ? '_' : *s, fp);
}

hv_status hv_mesh_write_obj(const hv_mesh *m, const char *path)
{
    if (hv_check_extension(path, ".obj", "a mesh") != HV_OK) return HV_ERR_INVALID;
    hv_atomic_file af;
    hv_status s = hv_atomic_open(&af, path, "wb");
    if (s != HV_OK) return s;
    FILE *fp = af.fp;
    fprintf(fp, "# written by hovox: %zu bodies, %zu vertices, %zu facets\n", m->nbodies, m->nv, m->nf);
    for (size_t i = 0; i < m->nv; ++i)
        fprintf(fp, "v %.9g %.9g %.9g\n", (double)m->xyz[3 * i], (double)m->xyz[3 * i + 1], (double)m->xyz[3 * i + 2]);
    int active = 0; /* a usemtl is in effect: OBJ carries it over to the next group */
    for (size_t b = 0; b < m->nbodies; ++b) {
        const hv_mesh_body *body = &m->bodies[b];
        fputs("o ", fp);
        put_name(fp, body->name);
        fputc('\n', fp);
        if (body->material != HV_MESH_NO_MATERIAL) {
            fputs("usemtl ", fp);
            put_name(fp, m->mats[body->material].name);
            fputc('\n', fp);
            active = 1;
        } else if (active) {
            fputs("usemtl\n", fp); /* no material from here on */
            active = 0;
        }
        for (size_t f = body->first_facet; f < body->first_facet + body->facet_count; ++f)
            fprintf(fp, "f %lu %lu %lu\n", (unsigned long)m->tri[3 * f] + 1, (unsigned long)m->tri[3 * f + 1] + 1,
                    (unsigned long)m->tri[3 * f + 2] + 1);
    }
    return hv_atomic_commit(&af);
}
