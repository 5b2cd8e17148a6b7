/* src/io/scan/metaimage.c - MetaImage volumes (Kitware's MetaIO, "MetaImage" in the ITK Software
 * Guide 4.1): .mha with the data after the header (ElementDataFile = LOCAL), .mhd naming a
 * detached data file; 3 dimensions, one channel, binary data raw or zlib-compressed. Offset and
 * TransformMatrix (row a = the direction of axis a) are ITK's physical space, LPS: they become RAS
 * (hovox/scan.h). */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "io/scan/scan_internal.h"

#define HEAD_MAX ((size_t)1 << 20)
#define BAD(...) hv_error_set(HV_ERR_BAD_INPUT, __VA_ARGS__)

typedef struct mha {
    scan_type type;
    int ndims, big, compressed, binary, channels;
    size_t dims[3];
    double spacing[3], offset[3], tm[9];
    int has_spacing;
    long long header_size;
    char datafile[1024], orient[8];
} mha;

static scan_type type_named(const char *v)
{
    static const struct { const char *n; scan_type t; } k[] = {
        {"MET_UCHAR", SCAN_U8}, {"MET_CHAR", SCAN_I8}, {"MET_SHORT", SCAN_I16}, {"MET_USHORT", SCAN_U16},
        {"MET_INT", SCAN_I32}, {"MET_UINT", SCAN_U32}, {"MET_LONG", SCAN_I32}, {"MET_ULONG", SCAN_U32},
        {"MET_LONG_LONG", SCAN_I64}, {"MET_ULONG_LONG", SCAN_U64}, {"MET_FLOAT", SCAN_F32}, {"MET_DOUBLE", SCAN_F64},
    };
    for (size_t i = 0; i < HV_COUNT(k); ++i)
        if (strcmp(v, k[i].n) == 0) return k[i].t;
    return SCAN_NONE;
}

static int truth(const char *v) { return strcasecmp(v, "true") == 0 || strcmp(v, "1") == 0; }

static hv_status numbers(const char *nm, int line, const char *key, const char *v, double *out, int n)
{
    const char *e;
    if (scan_numbers(v, out, n, &e) != n || *e)
        return BAD("%s: line %d: %s '%s' is not %d numbers", nm, line, key, v, n);
    return HV_OK;
}

static hv_status field(hv_scan *scan, mha *h, int line, const char *key, const char *v)
{
    const char *nm = scan->name;
    if (!strcasecmp(key, "ObjectType")) {
        if (strcasecmp(v, "Image")) return BAD("%s: line %d: ObjectType '%s' is not Image", nm, line, v);
    } else if (!strcasecmp(key, "NDims")) {
        if (strcmp(v, "3")) return BAD("%s: line %d: NDims '%s': hovox reads 3-D volumes", nm, line, v);
        h->ndims = 3;
    } else if (!strcasecmp(key, "DimSize")) {
        double d[3];
        hv_status st = numbers(nm, line, key, v, d, 3);
        if (st != HV_OK) return st;
        for (int a = 0; a < 3; ++a) {
            if (!(d[a] >= 1 && d[a] <= 2147483648.0) || d[a] != floor(d[a]))
                return BAD("%s: line %d: DimSize '%s' are not 3 sizes of at least 1", nm, line, v);
            h->dims[a] = (size_t)d[a];
        }
    } else if (!strcasecmp(key, "ElementType")) {
        h->type = type_named(v);
        if (h->type == SCAN_NONE) return BAD("%s: line %d: ElementType '%s' is not a scalar type hovox reads", nm, line, v);
    } else if (!strcasecmp(key, "ElementSpacing") || (!strcasecmp(key, "ElementSize") && !h->has_spacing)) {
        hv_status st = numbers(nm, line, key, v, h->spacing, 3);
        if (st != HV_OK) return st;
        for (int a = 0; a < 3; ++a)
            if (!(h->spacing[a] > 0)) return BAD("%s: line %d: %s '%s' is not 3 sizes above 0", nm, line, key, v);
        h->has_spacing = !strcasecmp(key, "ElementSpacing");
    } else if (!strcasecmp(key, "Offset") || !strcasecmp(key, "Position") || !strcasecmp(key, "Origin")) {
        return numbers(nm, line, key, v, h->offset, 3);
    } else if (!strcasecmp(key, "TransformMatrix") || !strcasecmp(key, "Rotation") || !strcasecmp(key, "Orientation")) {
        return numbers(nm, line, key, v, h->tm, 9);
    } else if (!strcasecmp(key, "BinaryData")) {
        h->binary = truth(v);
    } else if (!strcasecmp(key, "BinaryDataByteOrderMSB") || !strcasecmp(key, "ElementByteOrderMSB")) {
        h->big = truth(v);
    } else if (!strcasecmp(key, "CompressedData")) {
        h->compressed = truth(v);
    } else if (!strcasecmp(key, "ElementNumberOfChannels")) {
        h->channels = atoi(v);
        if (h->channels != 1)
            return BAD("%s: line %d: ElementNumberOfChannels '%s': hovox reads one channel", nm, line, v);
    } else if (!strcasecmp(key, "HeaderSize")) {
        char *e;
        h->header_size = strtoll(v, &e, 10);
        if (*e || h->header_size < -1) return BAD("%s: line %d: HeaderSize '%s' is not -1 or a count", nm, line, v);
    } else if (!strcasecmp(key, "AnatomicalOrientation")) {
        snprintf(h->orient, sizeof h->orient, "%.3s", v);
    } else if (!strcasecmp(key, "ElementDataFile")) {
        if (strcmp(v, "LIST") == 0 || strchr(v, '%') || strchr(v, ' '))
            return hv_error_set(HV_ERR_UNSUPPORTED, "%s: line %d: ElementDataFile '%s': data split over several files is "
                                "not read", nm, line, v);
        if (!*v || strlen(v) >= sizeof h->datafile) return BAD("%s: line %d: ElementDataFile is empty or too long", nm, line);
        memcpy(h->datafile, v, strlen(v) + 1);
    }
    return HV_OK;
}

/* The header up to the ElementDataFile line; *data_at just after it. */
static hv_status header(hv_scan *scan, mha *h, char *t, size_t len, size_t *data_at)
{
    const char *nm = scan->name;
    size_t p = 0;
    int line = 0;
    while (p < len) {
        size_t e = p;
        while (e < len && t[e] != '\n') ++e;
        ++line;
        size_t next = e < len ? e + 1 : e, end = e;
        if (end > p && t[end - 1] == '\r') --end;
        if (memchr(t + p, 0, end - p)) return BAD("%s: line %d: a NUL byte in the header", nm, line);
        t[end] = 0;
        char *l = t + p;
        while (*l == ' ' || *l == '\t') ++l;
        if (*l) {
            char *eq = strchr(l, '=');
            if (!eq) return BAD("%s: line %d: '%.60s' is not 'Key = Value'%s", nm, line, l,
                                line == 1 ? " (not a MetaImage header)" : "");
            char *k_end = eq;
            while (k_end > l && (k_end[-1] == ' ' || k_end[-1] == '\t')) --k_end;
            *k_end = 0;
            char *v = eq + 1;
            while (*v == ' ' || *v == '\t') ++v;
            size_t vl = strlen(v);
            while (vl && (v[vl - 1] == ' ' || v[vl - 1] == '\t')) v[--vl] = 0;
            hv_status st = field(scan, h, line, l, v);
            if (st != HV_OK) return st;
            if (!strcasecmp(l, "ElementDataFile")) {
                *data_at = next;
                return HV_OK;
            }
        }
        if (e == len && len == HEAD_MAX) break;
        p = next;
    }
    return BAD("%s: no ElementDataFile line ends the header%s", nm, len == HEAD_MAX ? " in its first MiB" : "");
}

hv_status scan_read_metaimage(hv_scan *scan, const char *path, const uint8_t *mem, size_t size,
                              const hv_scan_options *opts)
{
    char *t;
    size_t len, data_at = 0;
    hv_status st = scan_head(path, mem, size, HEAD_MAX, &t, &len);
    if (st != HV_OK) return st;
    mha h;
    memset(&h, 0, sizeof h);
    h.binary = 1;
    h.channels = 1;
    h.spacing[0] = h.spacing[1] = h.spacing[2] = 1;
    h.tm[0] = h.tm[4] = h.tm[8] = 1;
    scan->info.format = HV_SCAN_METAIMAGE;
    scan->info.format_name = "MetaImage";
    st = header(scan, &h, t, len, &data_at);
    free(t);
    if (st != HV_OK) return st;
    const char *nm = scan->name;
    if (h.ndims != 3) return BAD("%s: the header has no NDims = 3", nm);
    if (!h.dims[0]) return BAD("%s: the header has no DimSize", nm);
    if (h.type == SCAN_NONE) return BAD("%s: the header has no ElementType", nm);
    if (!h.binary) return hv_error_set(HV_ERR_UNSUPPORTED, "%s: BinaryData = False: text data is not read", nm);
    if ((double)h.dims[0] * (double)h.dims[1] * (double)h.dims[2] > 1e15)
        return BAD("%s: DimSize %zu %zu %zu is not a volume", nm, h.dims[0], h.dims[1], h.dims[2]);
    /* index -> LPS: column a = direction of axis a (row a of TransformMatrix) times its spacing */
    for (int a = 0; a < 3; ++a)
        for (int r = 0; r < 3; ++r) scan->m[4 * r + a] = h.tm[3 * a + r] * h.spacing[a];
    for (int r = 0; r < 3; ++r) scan->m[4 * r + 3] = h.offset[r];
    scan_lps_to_ras(scan->m);
    snprintf(scan->space, sizeof scan->space, "LPS (ITK physical space) -> RAS%s%s", h.orient[0] ? ", orientation " : "",
             h.orient);
    st = scan_check_affine(scan, "TransformMatrix and ElementSpacing");
    if (st != HV_OK) return st;
    snprintf(scan->sample_type, sizeof scan->sample_type, "%s", scan_type_name(h.type));
    snprintf(scan->encoding, sizeof scan->encoding, "%s", h.compressed ? "zlib" : "raw");

    scan_src s;
    char *df = NULL;
    if (strcasecmp(h.datafile, "LOCAL") != 0) {
        if (!path) return BAD("%s: a detached header (ElementDataFile %s) cannot be read from memory", nm, h.datafile);
        df = scan_sibling(path, h.datafile);
        if (!df) return HV_ERR_NOMEM;
        hv_input_note(df);
        st = scan_src_open_file(&s, df, df, 0);
        scan->info.files = 2;
    } else if (path) {
        st = scan_src_open_file(&s, path, nm, data_at);
    } else {
        scan_src_open_mem(&s, mem, size, nm, data_at);
    }
    if (st != HV_OK) {
        free(df);
        return st;
    }
    size_t count = h.dims[0] * h.dims[1] * h.dims[2];
    uint64_t need = (uint64_t)count * scan_type_size(h.type);
    if (h.header_size == -1 && !h.compressed) {
        if (scan_src_left(&s) >= need) s.pos = s.size - need;
    } else if (h.header_size > 0) {
        s.pos = HV_MIN(s.size, s.pos + (uint64_t)h.header_size);
    }
    if (s.fp && fseeko(s.fp, (off_t)s.pos, SEEK_SET) != 0) st = hv_error_set(HV_ERR_IO, "%s: cannot seek", s.name);
    if (st == HV_OK && !h.compressed && scan_src_left(&s) < need)
        st = BAD("%s: the header says %zu x %zu x %zu %s samples (%llu bytes); the file holds %llu after the header",
                 s.name, h.dims[0], h.dims[1], h.dims[2], scan_type_name(h.type), (unsigned long long)need,
                 (unsigned long long)scan_src_left(&s));
    if (st == HV_OK && h.compressed) st = scan_src_inflate(&s);
    if (st == HV_OK) st = scan_alloc(scan, h.dims, opts);
    if (st == HV_OK) st = scan_read_samples(&s, h.type, h.big, 1, 0, scan->data, count);
    if (st == HV_OK) st = scan_src_end(&s);
    scan_src_close(&s);
    free(df);
    return st;
}
