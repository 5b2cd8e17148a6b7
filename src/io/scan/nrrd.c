/* src/io/scan/nrrd.c - NRRD volumes (teem's "Definition of NRRD File Format", NRRD0001-0005):
 * .nrrd with attached data, .nhdr with a detached data file; 3 dimensions, one scalar type;
 * encodings raw, gzip and ascii (bzip2 and hex are refused); space directions and origin in a
 * named space (RAS/LAS/LPS, scanner-xyz, 3D-right-handed) or spacings and axis mins; space
 * units to mm. LPS and LAS spaces become RAS (hovox/scan.h). */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/scan/scan_internal.h"

#define HEAD_MAX ((size_t)1 << 20)

typedef struct nrrd {
    scan_type type;
    int dimension, big, endian_given, enc; /* enc: 0 raw, 1 gzip, 2 ascii */
    size_t sizes[3];
    int has_dirs, has_origin, has_spacings, has_mins, cell, space; /* space: 0 none/RAS, 1 LPS, 2 LAS */
    const char *space_name;
    double dirs[9], origin[3], spacings[3], mins[3], unit[3];
    long long byte_skip, line_skip;
    char datafile[1024];
} nrrd;

static scan_type type_named(const char *v)
{
    static const struct { const char *n; scan_type t; } k[] = {
        {"signed char", SCAN_I8}, {"int8", SCAN_I8}, {"int8_t", SCAN_I8},
        {"uchar", SCAN_U8}, {"unsigned char", SCAN_U8}, {"uint8", SCAN_U8}, {"uint8_t", SCAN_U8},
        {"short", SCAN_I16}, {"short int", SCAN_I16}, {"signed short", SCAN_I16}, {"signed short int", SCAN_I16},
        {"int16", SCAN_I16}, {"int16_t", SCAN_I16},
        {"ushort", SCAN_U16}, {"unsigned short", SCAN_U16}, {"unsigned short int", SCAN_U16}, {"uint16", SCAN_U16},
        {"uint16_t", SCAN_U16},
        {"int", SCAN_I32}, {"signed int", SCAN_I32}, {"int32", SCAN_I32}, {"int32_t", SCAN_I32},
        {"uint", SCAN_U32}, {"unsigned int", SCAN_U32}, {"uint32", SCAN_U32}, {"uint32_t", SCAN_U32},
        {"longlong", SCAN_I64}, {"long long", SCAN_I64}, {"long long int", SCAN_I64}, {"signed long long", SCAN_I64},
        {"signed long long int", SCAN_I64}, {"int64", SCAN_I64}, {"int64_t", SCAN_I64},
        {"ulonglong", SCAN_U64}, {"unsigned long long", SCAN_U64}, {"unsigned long long int", SCAN_U64},
        {"uint64", SCAN_U64}, {"uint64_t", SCAN_U64},
        {"float", SCAN_F32}, {"double", SCAN_F64},
    };
    for (size_t i = 0; i < HV_COUNT(k); ++i)
        if (strcmp(v, k[i].n) == 0) return k[i].t;
    return SCAN_NONE;
}

static double unit_mm(const char *u)
{
    if (!*u || strcmp(u, "mm") == 0 || strcmp(u, "millimeter") == 0) return 1;
    if (strcmp(u, "m") == 0 || strcmp(u, "meter") == 0) return 1000;
    if (strcmp(u, "cm") == 0) return 10;
    if (strcmp(u, "um") == 0 || strcmp(u, "micron") == 0 || strcmp(u, "\xc2\xb5m") == 0) return 0.001;
    return 0;
}

#define BAD(...) hv_error_set(HV_ERR_BAD_INPUT, __VA_ARGS__)

/* One "field: value" line (value trimmed, NUL-terminated). */
static hv_status field(hv_scan *scan, nrrd *n, int line, const char *key, char *v)
{
    const char *nm = scan->name;
    if (strcmp(key, "type") == 0) {
        n->type = type_named(v);
        if (n->type == SCAN_NONE) return BAD("%s: line %d: type '%s' is not a scalar type hovox reads", nm, line, v);
    } else if (strcmp(key, "dimension") == 0) {
        char *e;
        long d = strtol(v, &e, 10);
        if (*e || d != 3) return BAD("%s: line %d: dimension '%s': hovox reads 3-D volumes", nm, line, v);
        n->dimension = 3;
    } else if (strcmp(key, "sizes") == 0) {
        char *p = v;
        for (int a = 0; a < 3; ++a) {
            char *e;
            while (*p == ' ' || *p == '\t') ++p;
            long long s = strtoll(p, &e, 10);
            if (e == p || s < 1 || s > ((long long)1 << 31))
                return BAD("%s: line %d: sizes '%s' are not 3 sizes of at least 1", nm, line, v);
            n->sizes[a] = (size_t)s;
            p = e;
        }
        while (*p == ' ' || *p == '\t') ++p;
        if (*p) return BAD("%s: line %d: sizes '%s' are not 3 sizes", nm, line, v);
    } else if (strcmp(key, "endian") == 0) {
        if (strcmp(v, "little") && strcmp(v, "big")) return BAD("%s: line %d: endian '%s' is not little or big", nm, line, v);
        n->big = strcmp(v, "big") == 0;
        n->endian_given = 1;
    } else if (strcmp(key, "encoding") == 0) {
        if (!strcmp(v, "raw")) n->enc = 0;
        else if (!strcmp(v, "gzip") || !strcmp(v, "gz")) n->enc = 1;
        else if (!strcmp(v, "ascii") || !strcmp(v, "text") || !strcmp(v, "txt")) n->enc = 2;
        else if (!strcmp(v, "bzip2") || !strcmp(v, "bz2") || !strcmp(v, "hex"))
            return hv_error_set(HV_ERR_UNSUPPORTED, "%s: line %d: encoding '%s' is not read (raw, gzip and ascii are)", nm,
                                line, v);
        else return BAD("%s: line %d: encoding '%s' is not a NRRD encoding", nm, line, v);
    } else if (strcmp(key, "space") == 0) {
        static const struct { const char *n; int s; } k[] = {
            {"right-anterior-superior", 0}, {"RAS", 0}, {"scanner-xyz", 0}, {"3D-right-handed", 0},
            {"left-posterior-superior", 1}, {"LPS", 1}, {"left-anterior-superior", 2}, {"LAS", 2}};
        size_t i = 0;
        while (i < HV_COUNT(k) && strcmp(v, k[i].n)) ++i;
        if (i == HV_COUNT(k))
            return BAD("%s: line %d: space '%s' is not one hovox reads (RAS, LAS, LPS, scanner-xyz, 3D-right-handed)", nm,
                       line, v);
        n->space = k[i].s;
        n->space_name = k[i].n;
    } else if (strcmp(key, "space dimension") == 0) {
        if (strcmp(v, "3")) return BAD("%s: line %d: space dimension '%s': hovox reads 3-D spaces", nm, line, v);
    } else if (strcmp(key, "space directions") == 0) {
        const char *p = v;
        for (int a = 0; a < 3; ++a) {
            while (*p == ' ' || *p == '\t') ++p;
            if (*p != '(' || scan_numbers(p, n->dirs + 3 * a, 3, &p) != 3)
                return BAD("%s: line %d: space directions '%s' are not 3 vectors (x,y,z)", nm, line, v);
            while (*p == ' ' || *p == '\t') ++p;
            if (*p != ')' && a < 3) return BAD("%s: line %d: space directions '%s' are not 3 vectors (x,y,z)", nm, line, v);
            ++p;
        }
        n->has_dirs = 1;
    } else if (strcmp(key, "space origin") == 0) {
        const char *p = v;
        if (*p != '(' || scan_numbers(p, n->origin, 3, &p) != 3 || *p != ')')
            return BAD("%s: line %d: space origin '%s' is not a vector (x,y,z)", nm, line, v);
        n->has_origin = 1;
    } else if (strcmp(key, "spacings") == 0) {
        char *p = v;
        for (int a = 0; a < 3; ++a) {
            char *e;
            double d = strtod(p, &e);
            if (e == p) return BAD("%s: line %d: spacings '%s' are not 3 numbers", nm, line, v);
            n->spacings[a] = isfinite(d) && d > 0 ? d : 1; /* NaN: unknown */
            p = e;
        }
        n->has_spacings = 1;
    } else if (strcmp(key, "axis mins") == 0 || strcmp(key, "axismins") == 0) {
        char *p = v;
        for (int a = 0; a < 3; ++a) {
            char *e;
            double d = strtod(p, &e);
            if (e == p) return BAD("%s: line %d: axis mins '%s' are not 3 numbers", nm, line, v);
            n->mins[a] = isfinite(d) ? d : 0;
            p = e;
        }
        n->has_mins = 1;
    } else if (strcmp(key, "centers") == 0 || strcmp(key, "centerings") == 0) {
        n->cell = strstr(v, "cell") != NULL;
    } else if (strcmp(key, "space units") == 0) {
        char *p = v;
        for (int a = 0; a < 3; ++a) {
            while (*p == ' ' || *p == '\t') ++p;
            if (*p != '"') return BAD("%s: line %d: space units '%s' are not 3 quoted units", nm, line, v);
            char *q = strchr(p + 1, '"');
            if (!q) return BAD("%s: line %d: space units '%s' are not 3 quoted units", nm, line, v);
            *q = 0;
            n->unit[a] = unit_mm(p + 1);
            if (!(n->unit[a] > 0)) return BAD("%s: line %d: space unit '%s' is not a length hovox knows", nm, line, p + 1);
            p = q + 1;
        }
    } else if (strcmp(key, "byte skip") == 0 || strcmp(key, "byteskip") == 0) {
        char *e;
        n->byte_skip = strtoll(v, &e, 10);
        if (*e || n->byte_skip < -1) return BAD("%s: line %d: byte skip '%s' is not -1 or a count", nm, line, v);
    } else if (strcmp(key, "line skip") == 0 || strcmp(key, "lineskip") == 0) {
        char *e;
        n->line_skip = strtoll(v, &e, 10);
        if (*e || n->line_skip < 0 || n->line_skip > 1000000) return BAD("%s: line %d: line skip '%s' is not a count", nm, line, v);
    } else if (strcmp(key, "data file") == 0 || strcmp(key, "datafile") == 0) {
        if (strchr(v, ' ') || strcmp(v, "LIST") == 0 || strchr(v, '%'))
            return hv_error_set(HV_ERR_UNSUPPORTED, "%s: line %d: data file '%s': data split over several files is not read",
                                nm, line, v);
        if (strlen(v) >= sizeof n->datafile || !*v) return BAD("%s: line %d: data file name is empty or too long", nm, line);
        memcpy(n->datafile, v, strlen(v) + 1);
    } else if (strcmp(key, "block size") == 0 || strcmp(key, "blocksize") == 0) {
        return BAD("%s: line %d: type block is not read", nm, line);
    }
    return HV_OK; /* content, kinds, labels, min, max and the rest: not needed */
}

/* Parse the header; *data_at: the offset just after the blank line that ends it (0 when the
 * header is all of the text). */
static hv_status header(hv_scan *scan, nrrd *n, char *t, size_t len, size_t *data_at)
{
    const char *nm = scan->name;
    if (len < 8 || memcmp(t, "NRRD000", 7) != 0 || t[7] < '1' || t[7] > '5')
        return BAD("%s: not a NRRD file (it does not start with NRRD0001..NRRD0005)", nm);
    size_t p = 0;
    int line = 0;
    *data_at = 0;
    while (p < len) {
        size_t e = p;
        while (e < len && t[e] != '\n') ++e;
        if (e == len && len == HEAD_MAX) return BAD("%s: the header is longer than 1 MiB", nm);
        ++line;
        size_t next = e < len ? e + 1 : e;
        size_t end = e;
        if (end > p && t[end - 1] == '\r') --end;
        if (memchr(t + p, 0, end - p)) return BAD("%s: line %d: a NUL byte in the header", nm, line);
        if (end == p) { /* the blank line: data follows */
            *data_at = next;
            return HV_OK;
        }
        t[end] = 0;
        char *l = t + p;
        if (line > 1 && l[0] != '#') {
            char *c = strstr(l, ": ");
            if (!c && strstr(l, ":=") == NULL) return BAD("%s: line %d: '%.60s' is not 'field: value'", nm, line, l);
            if (c && (!strstr(l, ":=") || strstr(l, ":=") > c)) {
                *c = 0;
                char *v = c + 2;
                while (*v == ' ' || *v == '\t') ++v;
                size_t vl = strlen(v);
                while (vl && (v[vl - 1] == ' ' || v[vl - 1] == '\t')) v[--vl] = 0;
                hv_status st = field(scan, n, line, l, v);
                if (st != HV_OK) return st;
            }
        }
        p = next;
    }
    return HV_OK;
}

static hv_status read_ascii(hv_scan *scan, scan_src *s, size_t count)
{
    size_t cap = 1 << 16, len = 0, done = 0;
    char *buf = hv_malloc(cap + 1);
    if (!buf) return HV_ERR_NOMEM;
    hv_status st = HV_OK;
    int eof = 0;
    while (done < count) {
        size_t got = 0;
        if (!eof && len < cap) {
            st = scan_src_read(s, buf + len, cap - len, &got);
            if (st != HV_OK) break;
            if (got == 0) eof = 1;
            len += got;
        }
        buf[len] = 0;
        size_t p = 0;
        while (done < count) {
            while (p < len && (isspace((unsigned char)buf[p]) || buf[p] == ',')) ++p;
            size_t q = p;
            while (q < len && !isspace((unsigned char)buf[q]) && buf[q] != ',') ++q;
            if (q == len && !eof) break; /* a number may go on in the next chunk */
            if (q == p) break;
            char *e;
            char save = buf[q];
            buf[q] = 0;
            double d = strtod(buf + p, &e);
            buf[q] = save;
            if (e != buf + q || !isfinite(d)) {
                st = BAD("%s: ascii data: sample %zu '%.*s' is not a finite number", scan->name, done, (int)HV_MIN(q - p, (size_t)40),
                         buf + p);
                goto out;
            }
            scan->data[done++] = (float)d;
            p = q;
        }
        if (p == 0 && len == cap) {
            st = BAD("%s: ascii data: sample %zu is longer than 64 KiB", scan->name, done);
            break;
        }
        memmove(buf, buf + p, len - p);
        len -= p;
        if (eof && done < count) {
            st = BAD("%s: truncated: the ascii data holds %zu of %zu samples", scan->name, done, count);
            break;
        }
    }
out:
    free(buf);
    return st;
}

static hv_status skip_lines(scan_src *s, long long lines)
{
    uint8_t c;
    size_t got;
    while (lines > 0) {
        hv_status st = scan_src_read(s, &c, 1, &got);
        if (st != HV_OK) return st;
        if (!got) return BAD("%s: truncated: the file ends within the lines to skip", s->name);
        if (c == '\n') --lines;
    }
    return HV_OK;
}

static hv_status affine(hv_scan *scan, const nrrd *n)
{
    double *m = scan->m;
    memset(m, 0, 12 * sizeof *m);
    if (n->has_dirs) {
        for (int a = 0; a < 3; ++a)
            for (int r = 0; r < 3; ++r) m[4 * r + a] = n->dirs[3 * a + r] * n->unit[r];
        for (int r = 0; r < 3; ++r) m[4 * r + 3] = n->has_origin ? n->origin[r] * n->unit[r] : 0;
        if (n->space == 1) scan_lps_to_ras(m);
        if (n->space == 2) for (int c = 0; c < 4; ++c) m[c] = -m[c];
        snprintf(scan->space, sizeof scan->space, "%s%s", n->space_name ? n->space_name : "space directions (taken as RAS)",
                 n->space == 1 ? " -> RAS" : n->space == 2 ? " -> RAS" : "");
    } else {
        for (int a = 0; a < 3; ++a) {
            double sp = n->has_spacings ? n->spacings[a] : 1;
            m[5 * a] = sp;
            m[4 * a + 3] = n->has_mins ? n->mins[a] + (n->cell ? sp / 2 : 0) : 0;
        }
        snprintf(scan->space, sizeof scan->space, "spacings%s (no space: taken as RAS)", n->has_mins ? " and axis mins" : "");
    }
    return scan_check_affine(scan, "the space directions");
}

hv_status scan_read_nrrd(hv_scan *scan, const char *path, const uint8_t *mem, size_t size,
                         const hv_scan_options *opts)
{
    char *t;
    size_t len, data_at;
    hv_status st = scan_head(path, mem, size, HEAD_MAX, &t, &len);
    if (st != HV_OK) return st;
    nrrd n;
    memset(&n, 0, sizeof n);
    n.unit[0] = n.unit[1] = n.unit[2] = 1;
    scan->info.format = HV_SCAN_NRRD;
    scan->info.format_name = "NRRD";
    st = header(scan, &n, t, len, &data_at);
    free(t);
    if (st != HV_OK) return st;
    const char *nm = scan->name;
    if (n.type == SCAN_NONE) return BAD("%s: the header has no type field", nm);
    if (n.dimension != 3) return BAD("%s: the header has no dimension field", nm);
    if (!n.sizes[0]) return BAD("%s: the header has no sizes field", nm);
    if (n.enc != 2 && scan_type_size(n.type) > 1 && !n.endian_given)
        return BAD("%s: the header has no endian field (needed for %s samples)", nm, scan_type_name(n.type));
    if ((double)n.sizes[0] * (double)n.sizes[1] * (double)n.sizes[2] > 1e15)
        return BAD("%s: sizes %zu %zu %zu are not a volume", nm, n.sizes[0], n.sizes[1], n.sizes[2]);
    if (n.byte_skip == -1 && n.enc != 0) return BAD("%s: byte skip -1 is only for raw encoding", nm);
    st = affine(scan, &n);
    if (st != HV_OK) return st;
    snprintf(scan->sample_type, sizeof scan->sample_type, "%s", scan_type_name(n.type));
    snprintf(scan->encoding, sizeof scan->encoding, "%s", n.enc == 0 ? "raw" : n.enc == 1 ? "gzip" : "ascii");

    scan_src s;
    char *df = NULL;
    if (n.datafile[0]) {
        if (!path) return BAD("%s: a detached header (data file %s) cannot be read from memory", nm, n.datafile);
        df = scan_sibling(path, n.datafile);
        if (!df) return HV_ERR_NOMEM;
        hv_input_note(df);
        st = scan_src_open_file(&s, df, df, 0);
        scan->info.files = 2;
    } else {
        if (!data_at) {
            return BAD("%s: no blank line ends the header and no data file is named%s", nm,
                       path && hv_has_extension(path, ".nhdr") ? " (a .nhdr names its data file)" : "");
        }
        if (path) st = scan_src_open_file(&s, path, nm, data_at);
        else scan_src_open_mem(&s, mem, size, nm, data_at);
    }
    if (st != HV_OK) {
        free(df);
        return st;
    }
    size_t count = n.sizes[0] * n.sizes[1] * n.sizes[2];
    uint64_t need = (uint64_t)count * scan_type_size(n.type);
    st = skip_lines(&s, n.line_skip);
    if (st == HV_OK && n.enc == 0) {
        if (n.byte_skip == -1) {
            if (scan_src_left(&s) < need) goto short_file;
            s.pos = s.size - need;
            if (s.fp && fseeko(s.fp, (off_t)s.pos, SEEK_SET) != 0) st = hv_error_set(HV_ERR_IO, "%s: cannot seek", s.name);
        } else {
            if (scan_src_left(&s) < (uint64_t)n.byte_skip) goto short_file;
            s.pos += (uint64_t)n.byte_skip;
            if (s.fp && fseeko(s.fp, (off_t)s.pos, SEEK_SET) != 0) st = hv_error_set(HV_ERR_IO, "%s: cannot seek", s.name);
        }
        if (st == HV_OK && scan_src_left(&s) < need) goto short_file;
    }
    if (st == HV_OK && n.enc == 1) {
        st = scan_src_inflate(&s);
        uint8_t junk[4096];
        long long skip = n.byte_skip;
        while (st == HV_OK && skip > 0) {
            size_t k = (size_t)HV_MIN(skip, (long long)sizeof junk), got;
            st = scan_src_read(&s, junk, k, &got);
            if (st == HV_OK && got < k) st = BAD("%s: truncated: the data ends within the bytes to skip", s.name);
            skip -= (long long)k;
        }
    }
    if (st == HV_OK) st = scan_alloc(scan, n.sizes, opts);
    if (st == HV_OK) {
        if (n.enc == 2) st = read_ascii(scan, &s, count);
        else st = scan_read_samples(&s, n.type, n.big, 1, 0, scan->data, count);
    }
    if (st == HV_OK) st = scan_src_end(&s);
    scan_src_close(&s);
    free(df);
    return st;
short_file:
    st = BAD("%s: the header says %zu x %zu x %zu %s samples (%llu bytes); the file holds %llu after the header",
             s.name, n.sizes[0], n.sizes[1], n.sizes[2], scan_type_name(n.type), (unsigned long long)need,
             (unsigned long long)scan_src_left(&s));
    scan_src_close(&s);
    free(df);
    return st;
}
