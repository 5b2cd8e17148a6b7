/* src/io/mtl.c - Wavefront material libraries (.mtl, "MTL material format", Alias|Wavefront,
 * appendix to the OBJ specification): `newmtl` names a material, `Kd r g b` its diffuse colour,
 * `d` / `Tr` its opacity, `map_Kd [options] file` its diffuse texture (options -clamp, -o, -s
 * read; the others skipped by their argument counts). The display statements hovox does not use
 * (Ka, Ks, Ns, illum, map_Bump, the PBR extensions, ...) are skipped; what is read is checked:
 * numbers finite and in range, one message naming the file, the line and the value. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "io_internal.h"

void hv_mtl_free(hv_mtl *t)
{
    for (size_t i = 0; i < t->n; ++i) {
        free(t->m[i].name);
        free(t->m[i].lib_path);
        free(t->m[i].map);
    }
    free(t->m);
    memset(t, 0, sizeof *t);
}


static int is(const char *s, const char *e, const char *w)
{
    size_t n = strlen(w);
    return (size_t)(e - s) == n && memcmp(s, w, n) == 0;
}

typedef struct mtl_reader {
    const char *name;
    size_t line;
    hv_mtl *out;
} mtl_reader;

static hv_status number(const mtl_reader *r, const char *what, const char *s, const char *e, double lo,
                        double hi, float *out)
{
    char buf[64], q[72];
    size_t n = (size_t)(e - s);
    char *endp = buf;
    double v = NAN;
    if (n < sizeof buf) {
        memcpy(buf, s, n);
        buf[n] = '\0';
        v = strtod(buf, &endp);
    }
    if (n >= sizeof buf || endp != buf + n || !isfinite(v))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: %s is not a finite number: '%s'", r->name, r->line,
                            what, hv_quote(q, sizeof q, s, n));
    if (v < lo || v > hi)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: %s %g outside [%g, %g]", r->name, r->line, what, v,
                            lo, hi);
    *out = (float)v;
    return HV_OK;
}

static hv_mtl_material *current(const mtl_reader *r, const char *what)
{
    if (r->out->n == 0) {
        hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: '%s' before any newmtl", r->name, r->line, what);
        return NULL;
    }
    return &r->out->m[r->out->n - 1];
}

/* Kd r g b (g and b default to r), refusing the spectral and CIE XYZ forms. */
static hv_status kd(mtl_reader *r, const char *p, const char *e)
{
    hv_mtl_material *m = current(r, "Kd");
    if (!m) return HV_ERR_BAD_INPUT;
    const char *ts, *te;
    static const char *const what[] = {"Kd red", "Kd green", "Kd blue"};
    int k = 0;
    float v[3];
    hv_status s;
    for (; hv_io_next_token(&p, e, &ts, &te); ++k) {
        if (k == 0 && (is(ts, te, "spectral") || is(ts, te, "xyz")))
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: Kd %s is not supported (give r g b)", r->name,
                                r->line, is(ts, te, "xyz") ? "xyz" : "spectral");
        if (k == 3)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: Kd has more than 3 values", r->name, r->line);
        if ((s = number(r, what[k], ts, te, 0, 1, &v[k])) != HV_OK) return s;
    }
    if (k == 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: Kd has no values", r->name, r->line);
    if (k == 1) v[1] = v[2] = v[0];
    if (k == 2)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: Kd has 2 values (1 or 3)", r->name, r->line);
    memcpy(m->kd, v, sizeof v);
    m->has_kd = 1;
    return HV_OK;
}

/* d (opacity) or Tr (transparency): one number in [0, 1]; `d -halo f` is read as f. */
static hv_status opacity(mtl_reader *r, const char *p, const char *e, int transparency)
{
    const char *key = transparency ? "Tr" : "d";
    hv_mtl_material *m = current(r, key);
    if (!m) return HV_ERR_BAD_INPUT;
    const char *ts, *te;
    if (!hv_io_next_token(&p, e, &ts, &te))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: %s has no value", r->name, r->line, key);
    if (!transparency && is(ts, te, "-halo") && !hv_io_next_token(&p, e, &ts, &te))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: d -halo has no value", r->name, r->line);
    float v;
    hv_status s = number(r, key, ts, te, 0, 1, &v);
    if (s != HV_OK) return s;
    m->alpha = transparency ? 1 - v : v;
    return HV_OK;
}

/* map_Kd [-option args ...] file: -clamp on|off gives the tile style; -o and -s (u [v [w]]) move
 * and scale the coordinates; -blendu, -blendv, -cc, -mm, -t, -texres, -bm, -boost, -imfchan are
 * skipped with their arguments. The file is the rest of the line (names may hold blanks). */
static hv_status map_kd(mtl_reader *r, const char *p, const char *e)
{
    hv_mtl_material *m = current(r, "map_Kd");
    if (!m) return HV_ERR_BAD_INPUT;
    static const struct {
        const char *opt;
        int nmin, nmax; /* arguments */
    } skip[] = {{"-blendu", 1, 1}, {"-blendv", 1, 1}, {"-cc", 1, 1}, {"-mm", 2, 2}, {"-t", 1, 3},
                {"-texres", 1, 1}, {"-bm", 1, 1}, {"-boost", 1, 1}, {"-imfchan", 1, 1}};
    const char *ts, *te;
    char q[72];
    hv_status s;
    m->tile = HV_TILE_WRAP;
    m->offset[0] = m->offset[1] = 0;
    m->scale[0] = m->scale[1] = 1;
    for (;;) {
        const char *save = p;
        if (!hv_io_next_token(&p, e, &ts, &te))
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: map_Kd names no file", r->name, r->line);
        if (*ts != '-' || te - ts < 2) {
            p = save;
            break;
        }
        if (is(ts, te, "-clamp")) {
            if (!hv_io_next_token(&p, e, &ts, &te) || !(is(ts, te, "on") || is(ts, te, "off")))
                return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: map_Kd -clamp takes on or off", r->name,
                                    r->line);
            m->tile = is(ts, te, "on") ? HV_TILE_CLAMP : HV_TILE_WRAP;
            continue;
        }
        if (is(ts, te, "-o") || is(ts, te, "-s")) {
            int scale = ts[1] == 's';
            float *dst = scale ? m->scale : m->offset;
            const char *what = scale ? "map_Kd -s" : "map_Kd -o";
            int k = 0;
            for (; k < 3; ++k) {
                const char *s0 = p, *as, *ae;
                if (!hv_io_next_token(&p, e, &as, &ae)) break;
                char *endp;
                char buf[64];
                size_t n = (size_t)(ae - as);
                if (n >= sizeof buf) n = sizeof buf - 1;
                memcpy(buf, as, n);
                buf[n] = '\0';
                (void)strtod(buf, &endp);
                if (endp == buf || *endp) { /* not a number: the next option or the file */
                    p = s0;
                    break;
                }
                float v;
                if ((s = number(r, what, as, ae, -1e6, 1e6, &v)) != HV_OK) return s;
                if (k < 2) dst[k] = v;
            }
            if (k == 0)
                return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: %s needs a number", r->name, r->line, what);
            continue;
        }
        size_t i = 0;
        while (i < HV_COUNT(skip) && !is(ts, te, skip[i].opt)) ++i;
        if (i == HV_COUNT(skip))
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: map_Kd: unknown option '%s'", r->name, r->line,
                                hv_quote(q, sizeof q, ts, (size_t)(te - ts)));
        for (int k = 0; k < skip[i].nmax; ++k) {
            const char *s0 = p, *as, *ae;
            if (!hv_io_next_token(&p, e, &as, &ae) || (k >= skip[i].nmin && *as == '-' && ae - as > 1 &&
                                          !(as[1] >= '0' && as[1] <= '9'))) {
                if (k < skip[i].nmin)
                    return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: map_Kd %s needs %d value%s", r->name,
                                        r->line, skip[i].opt, skip[i].nmin, skip[i].nmin == 1 ? "" : "s");
                p = s0;
                break;
            }
        }
    }
    /* the file: the rest of the line, a comment cut off, blanks trimmed */
    while (p < e && hv_io_blank(*p)) ++p;
    const char *fe = p;
    while (fe < e && !(*fe == '#' && (fe == p || hv_io_blank(fe[-1])))) ++fe;
    while (fe > p && hv_io_blank(fe[-1])) --fe;
    if (fe == p) return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: map_Kd names no file", r->name, r->line);
    if (memchr(p, '\0', (size_t)(fe - p)))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: map_Kd file name holds a NUL byte", r->name, r->line);
    free(m->map);
    m->map = hv_malloc((size_t)(fe - p) + 1);
    if (!m->map) return HV_ERR_NOMEM;
    memcpy(m->map, p, (size_t)(fe - p));
    m->map[fe - p] = '\0';
    m->map_line = r->line;
    return HV_OK;
}

static hv_status newmtl(mtl_reader *r, const char *p, const char *e)
{
    while (p < e && hv_io_blank(*p)) ++p;
    const char *ne = p;
    while (ne < e && !(*ne == '#' && (ne == p || hv_io_blank(ne[-1])))) ++ne;
    while (ne > p && hv_io_blank(ne[-1])) --ne;
    if (ne == p) return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: newmtl without a name", r->name, r->line);
    if (memchr(p, '\0', (size_t)(ne - p))) /* the name would end there (found by fuzz_mtl: an empty name) */
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: newmtl name holds a NUL byte", r->name, r->line);
    hv_status s = hv_grow((void **)&r->out->m, &r->out->cap, r->out->n + 1, sizeof *r->out->m);
    if (s != HV_OK) return s;
    hv_mtl_material *m = &r->out->m[r->out->n];
    memset(m, 0, sizeof *m);
    m->alpha = 1;
    m->name = hv_malloc((size_t)(ne - p) + 1);
    m->lib_path = hv_strdup(r->name);
    r->out->n++; /* freed with the table from here on */
    if (!m->name || !m->lib_path) return HV_ERR_NOMEM;
    memcpy(m->name, p, (size_t)(ne - p));
    m->name[ne - p] = '\0';
    m->line = r->line;
    return HV_OK;
}

hv_status hv_mtl_parse(const void *data, size_t size, const char *name, hv_mtl *out)
{
    mtl_reader r = {name, 0, out};
    const char *p = data, *end = p + size;
    if (size >= 3 && memcmp(p, "\xEF\xBB\xBF", 3) == 0) p += 3;
    size_t line = 1;
    hv_status s = HV_OK;
    while (p < end && s == HV_OK) {
        r.line = line++;
        const char *eol = memchr(p, '\n', (size_t)(end - p));
        const char *ls = p, *le = eol ? eol : end;
        p = eol ? eol + 1 : end;
        const char *ks, *ke;
        if (!hv_io_next_token(&ls, le, &ks, &ke)) continue;
        if (is(ks, ke, "newmtl")) s = newmtl(&r, ls, le);
        else if (is(ks, ke, "Kd")) s = kd(&r, ls, le);
        else if (is(ks, ke, "d")) s = opacity(&r, ls, le, 0);
        else if (is(ks, ke, "Tr")) s = opacity(&r, ls, le, 1);
        else if (is(ks, ke, "map_Kd")) s = map_kd(&r, ls, le);
        /* every other statement is display information hovox does not print */
    }
    return s;
}

const hv_mtl_material *hv_mtl_find(const hv_mtl *t, const char *name)
{
    for (size_t i = 0; i < t->n; ++i) /* the first definition of a name counts */
        if (strcmp(t->m[i].name, name) == 0) return &t->m[i];
    return NULL;
}
