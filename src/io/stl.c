/* src/mesh/stl.c - STL input and output. Binary or ASCII is decided by content (a binary
 * file has exactly 84 + 50n bytes), never by the word "solid". Input is hostile: every
 * defect yields one message naming the file, the facet or line, and the value. */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/internal.h"
#include "io_internal.h"

#define STL_MAX_BYTES ((size_t)1 << 40)

static uint32_t read_u32le(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float read_f32le(const unsigned char *p)
{
    uint32_t u = read_u32le(p);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static const char *axis_name(int a) { return a == 0 ? "x" : a == 1 ? "y" : "z"; }

/* Length of a UTF-8 byte order mark at d (editors on Windows write one), else 0. */
static size_t bom_length(const unsigned char *d, size_t n)
{
    return n >= 3 && d[0] == 0xEF && d[1] == 0xBB && d[2] == 0xBF ? 3 : 0;
}

/* No NUL or control bytes (other than whitespace) in the first KiB. */
static int is_text(const unsigned char *d, size_t n)
{
    size_t lim = HV_MIN(n, (size_t)1024);
    for (size_t k = 0; k < lim; ++k)
        if (d[k] == 0 || (d[k] < 0x20 && !isspace(d[k]))) return 0;
    return 1;
}

/* Text starting with "solid" after an optional BOM and whitespace: an ASCII STL candidate. */
static int looks_ascii(const unsigned char *d, size_t n)
{
    size_t i = bom_length(d, n);
    while (i < n && isspace(d[i])) ++i;
    if (n - i < 5 || strncasecmp((const char *)d + i, "solid", 5) != 0) return 0;
    return is_text(d, n);
}

/* The error for text that is not an ASCII STL: quote its first word. */
static hv_status not_stl_text(const unsigned char *d, size_t n, const char *name)
{
    size_t i = bom_length(d, n);
    while (i < n && isspace(d[i])) ++i;
    size_t k = i;
    while (k < n && k - i < 24 && !isspace(d[k])) ++k;
    return hv_error_set(HV_ERR_BAD_INPUT,
                        "%s: not an STL file: text that starts with '%.*s', not 'solid'", name,
                        (int)(k - i), (const char *)d + i);
}

static hv_status parse_binary(const unsigned char *d, size_t size, const char *name,
                              hv_mesh **out)
{
    size_t nf = read_u32le(d + 80);
    if (nf == 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: binary STL contains no facets", name);
    float *soup = hv_malloc_array(nf, 9 * sizeof(float));
    float *normals = hv_malloc_array(nf, 3 * sizeof(float));
    if (!soup || !normals) {
        free(soup);
        free(normals);
        return HV_ERR_NOMEM;
    }
    (void)size;
    const unsigned char *p = d + 84;
    for (size_t f = 0; f < nf; ++f, p += 50) {
        for (int k = 0; k < 3; ++k) normals[3 * f + (size_t)k] = read_f32le(p + 4 * k);
        for (int k = 0; k < 9; ++k) {
            float x = read_f32le(p + 12 + 4 * k);
            if (!isfinite(x)) {
                free(soup);
                free(normals);
                return hv_error_set(HV_ERR_BAD_INPUT,
                                    "%s: facet %zu (byte %zu): vertex %d has a non-finite %s "
                                    "coordinate (%g)",
                                    name, f, (size_t)(p - d) + 12 + 4 * (size_t)k, k / 3,
                                    axis_name(k % 3), (double)x);
            }
            soup[9 * f + (size_t)k] = x;
        }
        for (int k = 0; k < 3; ++k)
            if (!isfinite(normals[3 * f + (size_t)k])) normals[3 * f + (size_t)k] = 0.0f;
    }
    hv_status s = hv_mesh_from_soup(soup, normals, nf, name, HV_MESH_STL_BINARY, out);
    free(soup);
    free(normals);
    return s;
}

/* ---- ASCII ------------------------------------------------------------------------------- */

typedef struct lexer {
    const char *s, *end;
    size_t line;
    const char *name;
    char tok[64]; /* current token, truncated for messages */
    const char *tstart;
    size_t tlen;
} lexer;

/* Next whitespace-separated token; 0 at end of input. */
static int next_token(lexer *lx)
{
    while (lx->s < lx->end && isspace((unsigned char)*lx->s)) {
        if (*lx->s == '\n') ++lx->line;
        ++lx->s;
    }
    if (lx->s >= lx->end) {
        lx->tlen = 0;
        lx->tok[0] = '\0';
        return 0;
    }
    lx->tstart = lx->s;
    while (lx->s < lx->end && !isspace((unsigned char)*lx->s)) ++lx->s;
    lx->tlen = (size_t)(lx->s - lx->tstart);
    size_t n = HV_MIN(lx->tlen, sizeof lx->tok - 1);
    for (size_t i = 0; i < n; ++i) {
        unsigned char c = (unsigned char)lx->tstart[i];
        lx->tok[i] = (char)(c >= 0x20 && c < 0x7F ? c : '?');
    }
    lx->tok[n] = '\0';
    return 1;
}

static int tok_is(const lexer *lx, const char *word)
{
    return lx->tlen == strlen(word) && strncasecmp(lx->tstart, word, lx->tlen) == 0;
}

static void skip_line(lexer *lx)
{
    while (lx->s < lx->end && *lx->s != '\n') ++lx->s;
}

static hv_status expect(lexer *lx, const char *word, size_t facet, const char *where)
{
    if (!next_token(lx))
        return hv_error_set(HV_ERR_BAD_INPUT,
                            "%s: line %zu: unexpected end of file %s facet %zu (expected '%s')",
                            lx->name, lx->line, where, facet, word);
    if (!tok_is(lx, word))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: expected '%s', got '%s'", lx->name,
                            lx->line, word, lx->tok);
    return HV_OK;
}

static hv_status read_number(lexer *lx, size_t facet, const char *what, float *out)
{
    if (!next_token(lx))
        return hv_error_set(HV_ERR_BAD_INPUT,
                            "%s: line %zu: unexpected end of file inside facet %zu (expected %s)",
                            lx->name, lx->line, facet, what);
    char buf[128];
    if (lx->tlen >= sizeof buf)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: facet %zu: %s is not a number: '%s...'",
                            lx->name, lx->line, facet, what, lx->tok);
    memcpy(buf, lx->tstart, lx->tlen);
    buf[lx->tlen] = '\0';
    char *endp;
    double v = strtod(buf, &endp);
    if (endp == buf || endp != buf + lx->tlen) /* the whole token: a NUL byte inside ends strtod */
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %zu: facet %zu: %s is not a number: '%s'",
                            lx->name, lx->line, facet, what, lx->tok);
    *out = (float)v;
    return HV_OK;
}

static hv_status parse_ascii(const char *d, size_t size, const char *name, hv_mesh **out)
{
    size_t bom = bom_length((const unsigned char *)d, size);
    lexer lx = {d + bom, d + size, 1, name, "", d + bom, 0};
    size_t cap = 0, nf = 0;
    float *soup = NULL, *normals = NULL;
    size_t ncap = 0;
    hv_status s = HV_OK;
    int solids = 0;
    while (next_token(&lx)) {
        if (!tok_is(&lx, "solid")) {
            s = hv_error_set(HV_ERR_BAD_INPUT,
                             solids ? "%s: line %zu: unexpected '%s' after 'endsolid'"
                                    : "%s: line %zu: expected 'solid', got '%s'",
                             name, lx.line, lx.tok);
            goto fail;
        }
        ++solids;
        skip_line(&lx); /* the solid's name */
        for (;;) {
            if (!next_token(&lx)) {
                s = hv_error_set(HV_ERR_BAD_INPUT,
                                 "%s: line %zu: unexpected end of file (expected 'facet' or "
                                 "'endsolid')",
                                 name, lx.line);
                goto fail;
            }
            if (tok_is(&lx, "endsolid")) {
                skip_line(&lx);
                break;
            }
            if (!tok_is(&lx, "facet")) {
                s = hv_error_set(HV_ERR_BAD_INPUT,
                                 "%s: line %zu: expected 'facet' or 'endsolid', got '%s'", name,
                                 lx.line, lx.tok);
                goto fail;
            }
            if ((s = hv_grow((void **)&soup, &cap, nf + 1, 9 * sizeof(float))) != HV_OK ||
                (s = hv_grow((void **)&normals, &ncap, nf + 1, 3 * sizeof(float))) != HV_OK)
                goto fail;
            if ((s = expect(&lx, "normal", nf, "inside")) != HV_OK) goto fail;
            for (int k = 0; k < 3; ++k) {
                char what[32];
                snprintf(what, sizeof what, "normal %s", axis_name(k));
                if ((s = read_number(&lx, nf, what, &normals[3 * nf + (size_t)k])) != HV_OK)
                    goto fail;
                if (!isfinite(normals[3 * nf + (size_t)k])) normals[3 * nf + (size_t)k] = 0.0f;
            }
            if ((s = expect(&lx, "outer", nf, "inside")) != HV_OK ||
                (s = expect(&lx, "loop", nf, "inside")) != HV_OK)
                goto fail;
            for (int v = 0; v < 3; ++v) {
                if ((s = expect(&lx, "vertex", nf, "inside")) != HV_OK) goto fail;
                for (int k = 0; k < 3; ++k) {
                    char what[32];
                    snprintf(what, sizeof what, "vertex %d %s", v, axis_name(k));
                    float x;
                    if ((s = read_number(&lx, nf, what, &x)) != HV_OK) goto fail;
                    if (!isfinite(x)) {
                        s = hv_error_set(HV_ERR_BAD_INPUT,
                                         "%s: line %zu: facet %zu: vertex %d has a non-finite %s "
                                         "coordinate (%s)",
                                         name, lx.line, nf, v, axis_name(k), lx.tok);
                        goto fail;
                    }
                    soup[9 * nf + 3 * (size_t)v + (size_t)k] = x;
                }
            }
            if ((s = expect(&lx, "endloop", nf, "inside")) != HV_OK ||
                (s = expect(&lx, "endfacet", nf, "inside")) != HV_OK)
                goto fail;
            ++nf;
        }
    }
    if (nf == 0) {
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: ASCII STL contains no facets", name);
        goto fail;
    }
    s = hv_mesh_from_soup(soup, normals, nf, name, HV_MESH_STL_ASCII, out);
fail:
    free(soup);
    free(normals);
    return s;
}

hv_status hv_mesh_parse_stl(const void *data, size_t size, const char *name, hv_mesh **out)
{
    *out = NULL;
    const unsigned char *d = data;
    if (size == 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: empty file (0 bytes)", name);
    if (size >= 84) {
        uint64_t n = read_u32le(d + 80);
        uint64_t need = 84 + 50 * n;
        if (need == size) return parse_binary(d, size, name, out);
        if (looks_ascii(d, size)) return parse_ascii((const char *)data, size, name, out);
        if (is_text(d, size)) return not_stl_text(d, size, name);
        if (need > size)
            return hv_error_set(HV_ERR_BAD_INPUT,
                                "%s: truncated binary STL: header declares %llu facets "
                                "(%llu bytes) but the file has %zu bytes",
                                name, (unsigned long long)n, (unsigned long long)need, size);
        return hv_error_set(HV_ERR_BAD_INPUT,
                            "%s: binary STL has %llu bytes of trailing data after its %llu "
                            "facets (file %zu bytes, expected %llu)",
                            name, (unsigned long long)(size - need), (unsigned long long)n, size,
                            (unsigned long long)need);
    }
    if (looks_ascii(d, size)) return parse_ascii((const char *)data, size, name, out);
    if (is_text(d, size) && size > 0) return not_stl_text(d, size, name);
    return hv_error_set(HV_ERR_BAD_INPUT,
                        "%s: not an STL file: %zu bytes, too short for a binary header (84) "
                        "and not ASCII 'solid'",
                        name, size);
}

hv_status hv_mesh_load_stl(const char *path, hv_mesh **out)
{
    *out = NULL;
    char *data;
    size_t size;
    hv_status s = hv_read_file(path, STL_MAX_BYTES, &data, &size);
    if (s == HV_OK) hv_input_note(path);
    if (s != HV_OK) return s;
    s = hv_mesh_parse_stl(data, size, path, out);
    free(data);
    return s;
}

/* ---- output ------------------------------------------------------------------------------ */

static void put_u32le(unsigned char *p, uint32_t u)
{
    p[0] = (unsigned char)u;
    p[1] = (unsigned char)(u >> 8);
    p[2] = (unsigned char)(u >> 16);
    p[3] = (unsigned char)(u >> 24);
}

static void facet_normal(const hv_mesh *m, size_t f, float n[3])
{
    const float *a = m->xyz + 3 * (size_t)m->tri[3 * f], *b = m->xyz + 3 * (size_t)m->tri[3 * f + 1],
                *c = m->xyz + 3 * (size_t)m->tri[3 * f + 2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2], z = u[0] * v[1] - u[1] * v[0];
    double l = sqrt(x * x + y * y + z * z);
    if (l > 0) {
        x /= l;
        y /= l;
        z /= l;
    }
    n[0] = (float)x;
    n[1] = (float)y;
    n[2] = (float)z;
}

hv_status hv_mesh_write_stl(const hv_mesh *m, const char *path, int ascii)
{
    if (hv_check_extension(path, ".stl", "a mesh") != HV_OK) return HV_ERR_INVALID;
    hv_atomic_file af;
    hv_status s = hv_atomic_open(&af, path, "wb");
    if (s != HV_OK) return s;
    if (ascii) {
        fprintf(af.fp, "solid hovox\n");
        for (size_t f = 0; f < m->nf; ++f) {
            float n[3];
            facet_normal(m, f, n);
            fprintf(af.fp, "  facet normal %.9g %.9g %.9g\n    outer loop\n", (double)n[0],
                    (double)n[1], (double)n[2]);
            for (int k = 0; k < 3; ++k) {
                const float *p = m->xyz + 3 * (size_t)m->tri[3 * f + (size_t)k];
                fprintf(af.fp, "      vertex %.9g %.9g %.9g\n", (double)p[0], (double)p[1],
                        (double)p[2]);
            }
            fprintf(af.fp, "    endloop\n  endfacet\n");
        }
        fprintf(af.fp, "endsolid hovox\n");
    } else {
        unsigned char header[84] = "binary STL written by hovox";
        put_u32le(header + 80, (uint32_t)m->nf);
        fwrite(header, 1, sizeof header, af.fp);
        for (size_t f = 0; f < m->nf; ++f) {
            unsigned char rec[50] = {0};
            float vals[12];
            facet_normal(m, f, vals);
            for (int k = 0; k < 3; ++k)
                memcpy(vals + 3 + 3 * k, m->xyz + 3 * (size_t)m->tri[3 * f + (size_t)k], 3 * sizeof(float));
            for (int k = 0; k < 12; ++k) {
                uint32_t u;
                memcpy(&u, &vals[k], sizeof u);
                put_u32le(rec + 4 * k, u);
            }
            fwrite(rec, 1, sizeof rec, af.fp);
        }
    }
    return hv_atomic_commit(&af);
}
