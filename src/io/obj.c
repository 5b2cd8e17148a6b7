/* src/mesh/obj.c - Wavefront OBJ input: vertices, polygon faces (fan-triangulated), `o`/`g`
 * groups as bodies, `usemtl` names as materials. A strict reader for hostile input: every
 * index is checked against the vertices defined above it, every coordinate must be a finite
 * float, and every defect is one message naming the file, the line and the value. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "io_internal.h"


typedef struct obj_reader {
    const char *name;
    size_t line; /* where the statement being read starts */
    float *xyz;  /* 3 per vertex */
    size_t nv, vcap;
    size_t nvt, nvn; /* counted for the index checks; their values are not used */
    uint32_t *tri;   /* 3 per triangle, file order */
    int32_t *tbody, *tmat;
    size_t nt, tcap, bcap, mcap;
    hv_names bodies, mats;
    int32_t body, mat;      /* current body and material (-1: none) */
    int body_new, mat_new;  /* an o/g or usemtl since the last face: look the name up there */
    hv_buf body_name, mat_name;
    size_t ignored;         /* l and p statements */
    uint32_t *poly;
    size_t pcap;
} obj_reader;

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/* The next token of [*p, e) into [*ts, *te); 0 at the end of the statement (or a comment). */
static int next_tok(const char **p, const char *e, const char **ts, const char **te)
{
    const char *s = *p;
    while (s < e && is_blank(*s)) ++s;
    if (s == e || *s == '#') {
        *p = e;
        return 0;
    }
    *ts = s;
    while (s < e && !is_blank(*s)) ++s;
    *te = s;
    *p = s;
    return 1;
}

/* The rest of the statement, trimmed, a comment cut off: a name (o, g, usemtl). */
static void rest_of(const char *p, const char *e, const char **rs, const char **re)
{
    while (p < e && is_blank(*p)) ++p;
    const char *q = p;
    while (q < e && !(*q == '#' && (q == p || is_blank(q[-1])))) ++q;
    while (q > p && is_blank(q[-1])) --q;
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
    char buf[80];
    size_t n = (size_t)(e - s);
    if (n >= sizeof buf) return bad_coord(r, what, "number", s, n);
    memcpy(buf, s, n);
    buf[n] = '\0';
    char *endp;
    float v = strtof(buf, &endp);
    if (endp != buf + n) return bad_coord(r, what, "number", s, n);
    if (!isfinite(v)) return bad_coord(r, what, "finite float", s, n);
    *out = v;
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
    for (; next_tok(&p, e, &ts, &te); ++k) {
        if (k == 7)
            return hv_error_set(HV_ERR_BAD_INPUT,
                                "%s: line %zu: vertex has more than 7 values (x y z [w], or x y z and a "
                                "colour)",
                                r->name, r->line);
        float v = 0;
        if ((s = parse_coord(r, ts, te, what[k], &v)) != HV_OK) return s;
        if (k < 3) r->xyz[3 * r->nv + (size_t)k] = v; /* w and colours: read, not used */
    }
    if (k < 3)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: vertex has %d coordinate%s, 3 needed", r->name,
                            r->line, k, k == 1 ? "" : "s");
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

/* One corner of a face: v, v/vt, v//vn or v/vt/vn. */
static hv_status corner_ref(const obj_reader *r, size_t corner, const char *s, const char *e, uint32_t *v)
{
    const char *a = memchr(s, '/', (size_t)(e - s));
    const char *ve = a ? a : e;
    hv_status st = resolve(r, corner, s, (size_t)(ve - s), r->nv, "vertex", v);
    if (st != HV_OK || !a) return st;
    const char *b = memchr(a + 1, '/', (size_t)(e - a - 1));
    uint32_t ignored;
    if (b != a + 1 && (st = resolve(r, corner, a + 1, (size_t)((b ? b : e) - a - 1), r->nvt,
                                    "texture coordinate", &ignored)) != HV_OK)
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
    while (next_tok(&p, e, &ts, &te)) {
        if ((s = hv_grow((void **)&r->poly, &r->pcap, n + 1, sizeof *r->poly)) != HV_OK) return s;
        if ((s = corner_ref(r, n + 1, ts, te, &r->poly[n])) != HV_OK) return s;
        ++n;
    }
    if (n < 3)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: face has %zu vertices, at least 3 needed", r->name,
                            r->line, n);
    if ((s = face_owner(r)) != HV_OK) return s;
    size_t add = n - 2; /* a fan around the first corner */
    if ((s = hv_grow((void **)&r->tri, &r->tcap, 3 * (r->nt + add), sizeof *r->tri)) != HV_OK ||
        (s = hv_grow((void **)&r->tbody, &r->bcap, r->nt + add, sizeof *r->tbody)) != HV_OK ||
        (s = hv_grow((void **)&r->tmat, &r->mcap, r->nt + add, sizeof *r->tmat)) != HV_OK)
        return s;
    for (size_t k = 1; k + 1 < n; ++k, ++r->nt) {
        r->tri[3 * r->nt] = r->poly[0];
        r->tri[3 * r->nt + 1] = r->poly[k];
        r->tri[3 * r->nt + 2] = r->poly[k + 1];
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
    static const char *const ignored[] = {"s", "mtllib", "mg", "maplib", "usemap", "lod", "bevel", "c_interp",
                                          "d_interp", "shadow_obj", "trace_obj", "ctech", "stech", NULL};
    static const char *const freeform[] = {"vp", "cstype", "deg", "bmat", "step", "curv", "curv2", "surf",
                                           "parm", "trim", "hole", "scrv", "sp", "end", "con", NULL};
    const char *ks, *ke;
    if (!next_tok(&p, e, &ks, &ke)) return HV_OK; /* blank or comment */
    if (word_is(ks, ke, "v")) return vertex(r, p, e);
    if (word_is(ks, ke, "f")) return face(r, p, e);
    if (word_is(ks, ke, "vt")) return r->nvt++, HV_OK;
    if (word_is(ks, ke, "vn")) return r->nvn++, HV_OK;
    const char *ns, *ne;
    if (word_is(ks, ke, "o") || word_is(ks, ke, "g")) {
        rest_of(p, e, &ns, &ne);
        r->body_name.len = 0;
        hv_buf_append(&r->body_name, ns, (size_t)(ne - ns));
        r->body_new = 1;
        return r->body_name.failed ? HV_ERR_NOMEM : HV_OK;
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
    while (e > s && is_blank(e[-1])) --e;
    return e > s && e[-1] == '\\';
}

/* The triangles grouped by body (first appearance order), as a soup, with their materials. */
static hv_status finish(obj_reader *r, hv_mesh **out)
{
    size_t nb = r->bodies.n, nm = r->mats.n;
    float *soup = hv_malloc_array(r->nt, 9 * sizeof(float));
    int32_t *fmat = nm ? hv_malloc_array(r->nt, sizeof *fmat) : NULL;
    size_t *at = hv_calloc(nb + 1, sizeof *at);
    hv_mesh_body *bodies = hv_calloc(nb, sizeof *bodies);
    hv_mesh_material *mats = nm ? hv_calloc(nm, sizeof *mats) : NULL;
    hv_status s = HV_OK;
    if (!soup || (nm && (!fmat || !mats)) || !at || !bodies) {
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
    for (size_t t = 0; t < r->nt; ++t) {
        size_t f = at[r->tbody[t]]++;
        for (int c = 0; c < 3; ++c) memcpy(soup + 9 * f + 3 * c, r->xyz + 3 * (size_t)r->tri[3 * t + (size_t)c], 3 * sizeof(float));
        if (fmat) fmat[f] = r->tmat[t];
    }
    s = hv_mesh_build(soup, r->nt, r->name, HV_MESH_OBJ, bodies, nb, mats, nm, fmat, out);
done:
    free(soup);
    free(fmat);
    free(at);
    free(bodies);
    free(mats);
    return s;
}

hv_status hv_mesh_parse_obj(const void *data, size_t size, const char *name, hv_mesh **out)
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
                while (bs > ls && is_blank(bs[-1])) --bs;
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
    if (s == HV_OK) s = finish(&r, out);
    free(r.xyz);
    free(r.tri);
    free(r.tbody);
    free(r.tmat);
    free(r.poly);
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
