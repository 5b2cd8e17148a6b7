/* src/io/scan/scan.c - scanner volumes: the scan handle, the format dispatch (by extension; a
 * directory is a DICOM series), the byte source every reader reads through (a file or memory,
 * raw or inflated by zlib), sample conversion and the memory budget checked before allocating. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "io/scan/scan_internal.h"

/* ---- options ---------------------------------------------------------------------------------- */

#define OFF(f) offsetof(hv_scan_options, f)
static const hv_option k_opts[] = {
    {.key = "max_memory", .kind = HV_OPT_BYTES, .offset = OFF(max_memory), .meta = "SIZE",
     .help = "refuse a volume whose data would need more (4 bytes a sample; default: half of RAM), e.g. 8G",
     .section = "Resources"},
};
#undef OFF

void hv_scan_options_init(hv_scan_options *opts) { memset(opts, 0, sizeof *opts); }
static void init_void(void *o) { hv_scan_options_init(o); }

const hv_option_set *hv_scan_option_set(void)
{
    static const hv_option_set set = {"scan", k_opts, (int)HV_COUNT(k_opts), sizeof(hv_scan_options),
                                      init_void, NULL, 0, NULL, NULL, NULL, 0};
    return &set;
}

/* ---- sample types ------------------------------------------------------------------------------ */

size_t scan_type_size(scan_type t)
{
    static const size_t k[] = {0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8};
    return (unsigned)t < HV_COUNT(k) ? k[t] : 0;
}

const char *scan_type_name(scan_type t)
{
    static const char *const k[] = {"none", "uint8", "int8", "uint16", "int16", "uint32", "int32",
                                    "uint64", "int64", "float32", "float64"};
    return (unsigned)t < HV_COUNT(k) ? k[t] : "none";
}

static uint64_t load_u(const uint8_t *p, size_t n, int big)
{
    uint64_t v = 0;
    for (size_t k = 0; k < n; ++k) v |= (uint64_t)p[big ? n - 1 - k : k] << (8 * k);
    return v;
}

void scan_convert(const uint8_t *p, scan_type t, int big, double slope, double intercept, float *out,
                  size_t count)
{
    size_t w = scan_type_size(t);
    for (size_t i = 0; i < count; ++i, p += w) {
        uint64_t u = load_u(p, w, big);
        double v;
        switch (t) {
        case SCAN_U8: case SCAN_U16: case SCAN_U32: case SCAN_U64: v = (double)u; break;
        case SCAN_I8: v = (double)(int8_t)u; break;
        case SCAN_I16: v = (double)(int16_t)u; break;
        case SCAN_I32: v = (double)(int32_t)u; break;
        case SCAN_I64: v = (double)(int64_t)u; break;
        case SCAN_F32: {
            uint32_t b = (uint32_t)u;
            float f;
            memcpy(&f, &b, 4);
            v = f;
            break;
        }
        case SCAN_F64: memcpy(&v, &u, 8); break;
        default: v = 0; break;
        }
        out[i] = (float)(v * slope + intercept);
    }
}

/* ---- the byte source --------------------------------------------------------------------------- */

#define ZCHUNK (1u << 16)

hv_status scan_src_open_file(scan_src *s, const char *path, const char *name, uint64_t offset)
{
    memset(s, 0, sizeof *s);
    s->name = name;
    struct stat st;
    s->fp = fopen(path, "rb");
    if (!s->fp) return hv_error_set(HV_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    if (fstat(fileno(s->fp), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(s->fp);
        s->fp = NULL;
        return hv_error_set(HV_ERR_IO, "%s: not a regular file", path);
    }
    s->size = (uint64_t)st.st_size;
    s->pos = HV_MIN(offset, s->size);
    if (fseeko(s->fp, (off_t)s->pos, SEEK_SET) != 0) {
        fclose(s->fp);
        s->fp = NULL;
        return hv_error_set(HV_ERR_IO, "%s: cannot seek: %s", path, strerror(errno));
    }
    return HV_OK;
}

void scan_src_open_mem(scan_src *s, const uint8_t *data, size_t size, const char *name, uint64_t offset)
{
    memset(s, 0, sizeof *s);
    s->name = name;
    s->mem = data;
    s->size = size;
    s->pos = HV_MIN(offset, (uint64_t)size);
}

uint64_t scan_src_left(const scan_src *s) { return s->size - s->pos; }

static hv_status raw_read(scan_src *s, uint8_t *buf, size_t n, size_t *got)
{
    size_t k = (size_t)HV_MIN((uint64_t)n, s->size - s->pos);
    if (s->mem) {
        memcpy(buf, s->mem + s->pos, k);
    } else if (k) {
        size_t r = fread(buf, 1, k, s->fp);
        if (r != k && ferror(s->fp)) return hv_error_set(HV_ERR_IO, "%s: read error: %s", s->name, strerror(errno));
        k = r;
    }
    s->pos += k;
    *got = k;
    return HV_OK;
}

hv_status scan_src_inflate(scan_src *s)
{
    s->zin = hv_malloc(ZCHUNK);
    if (!s->zin) return HV_ERR_NOMEM;
    memset(&s->zs, 0, sizeof s->zs);
    if (inflateInit2(&s->zs, 15 + 32) != Z_OK) {
        free(s->zin);
        s->zin = NULL;
        return hv_error_set(HV_ERR_NOMEM, "%s: cannot start zlib", s->name);
    }
    s->inflating = 1;
    return HV_OK;
}

hv_status scan_src_read(scan_src *s, void *buf, size_t n, size_t *got)
{
    uint8_t *o = buf;
    *got = 0;
    if (!s->inflating) {
        hv_status st = raw_read(s, o, n, got);
        s->out += *got;
        return st;
    }
    while (*got < n && !s->zend) {
        if (s->zs.avail_in == 0) {
            size_t k;
            hv_status st = raw_read(s, s->zin, ZCHUNK, &k);
            if (st != HV_OK) return st;
            if (k == 0) break; /* the compressed stream is cut short: the caller sees fewer bytes */
            s->zs.next_in = s->zin;
            s->zs.avail_in = (uInt)k;
        }
        size_t want = HV_MIN(n - *got, (size_t)1 << 30);
        s->zs.next_out = o + *got;
        s->zs.avail_out = (uInt)want;
        int r = inflate(&s->zs, Z_NO_FLUSH);
        *got += want - s->zs.avail_out;
        if (r == Z_STREAM_END) {
            s->zend = 1;
        } else if (r == Z_BUF_ERROR) {
            if (s->zs.avail_in == 0) continue; /* needs input */
            break;
        } else if (r != Z_OK) {
            s->out += *got;
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: compressed data is damaged after %llu bytes (zlib: %s)",
                                s->name, (unsigned long long)s->out, s->zs.msg ? s->zs.msg : "error");
        }
    }
    s->out += *got;
    return HV_OK;
}

void scan_src_close(scan_src *s)
{
    if (s->inflating) inflateEnd(&s->zs);
    free(s->zin);
    if (s->fp) fclose(s->fp);
    memset(s, 0, sizeof *s);
}

/* ---- data -------------------------------------------------------------------------------------- */

hv_status scan_alloc(hv_scan *scan, const size_t dims[3], const hv_scan_options *opts)
{
    uint64_t n = 1;
    for (int a = 0; a < 3; ++a) {
        if (dims[a] == 0 || n > (UINT64_MAX / 8) / dims[a])
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: %zu x %zu x %zu samples is not a volume", scan->name,
                                dims[0], dims[1], dims[2]);
        n *= dims[a];
    }
    uint64_t bytes = n * sizeof(float);
    uint64_t budget = hv_memory_budget(opts ? opts->max_memory : 0);
    if ((budget && bytes > budget) || bytes > (uint64_t)SIZE_MAX / 2) {
        char need[32], have[32];
        return hv_error_option(HV_ERR_LIMIT, "%s: the data (%zu x %zu x %zu samples) needs %s, more than the limit of %s ({max_memory})",
                               scan->name, dims[0], dims[1], dims[2], hv_size_text(need, sizeof need, (double)bytes),
                               hv_size_text(have, sizeof have, (double)budget));
    }
    scan->data = hv_malloc_big((size_t)n, sizeof(float));
    if (!scan->data) return HV_ERR_NOMEM;
    memcpy(scan->dims, dims, sizeof scan->dims);
    return HV_OK;
}

hv_status scan_read_samples(scan_src *s, scan_type t, int big, double slope, double intercept,
                            float *out, size_t count)
{
    size_t w = scan_type_size(t), chunk = (1u << 20) / w, done = 0;
    uint8_t *buf = hv_malloc(chunk * w);
    if (!buf) return HV_ERR_NOMEM;
    hv_status st = HV_OK;
    while (done < count) {
        size_t k = HV_MIN(chunk, count - done), got;
        st = scan_src_read(s, buf, k * w, &got);
        if (st != HV_OK) break;
        if (got < k * w) {
            st = hv_error_set(HV_ERR_BAD_INPUT, "%s: truncated: the data ends after %llu of %llu bytes", s->name,
                              (unsigned long long)(done * w + got), (unsigned long long)count * w);
            break;
        }
        scan_convert(buf, t, big, slope, intercept, out + done, k);
        done += k;
        if ((done & ((1u << 24) - 1)) < k && hv_cancel_requested()) {
            st = hv_error_set(HV_ERR_CANCELLED, "cancelled");
            break;
        }
    }
    free(buf);
    return st;
}

hv_status scan_src_end(scan_src *s)
{
    if (!s->inflating || s->zend) return HV_OK;
    uint8_t b;
    size_t got;
    hv_status st = scan_src_read(s, &b, 1, &got);
    if (st != HV_OK) return st;
    if (!s->zend)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: truncated: the compressed stream stops without its end (%llu bytes read)",
                            s->name, (unsigned long long)s->pos);
    return HV_OK;
}

hv_status scan_finish(hv_scan *scan)
{
    size_t n = scan->dims[0] * scan->dims[1] * scan->dims[2];
    float lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < n; ++i) {
        float v = scan->data[i];
        if (!isfinite(v)) {
            size_t x = i % scan->dims[0], y = i / scan->dims[0] % scan->dims[1], z = i / scan->dims[0] / scan->dims[1];
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: sample (%zu, %zu, %zu) is %g, not a finite number", scan->name, x,
                                y, z, (double)v);
        }
        lo = v < lo ? v : lo;
        hi = v > hi ? v : hi;
    }
    scan->info.value_min = lo;
    scan->info.value_max = hi;
    scan->info.sample_type = scan->sample_type;
    scan->info.encoding = scan->encoding;
    scan->info.space = scan->space;
    scan->info.unit = scan->unit;
    return scan_check_affine(scan, "the index-to-world transform");
}

hv_status scan_check_affine(const hv_scan *scan, const char *what)
{
    const double *m = scan->m;
    for (int i = 0; i < 12; ++i)
        if (!isfinite(m[i])) return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s has a non-finite entry", scan->name, what);
    double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
                 m[2] * (m[4] * m[9] - m[5] * m[8]);
    double scale = 0;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) scale = HV_MAX(scale, fabs(m[4 * r + c]));
    if (!(scale > 0) || !(fabs(det) > 1e-12 * scale * scale * scale) || scale > 1e6)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s is singular or absurd (voxel axes [%g %g %g], [%g %g %g], [%g %g %g])",
                            scan->name, what, m[0], m[4], m[8], m[1], m[5], m[9], m[2], m[6], m[10]);
    return HV_OK;
}

void scan_lps_to_ras(double m[12])
{
    for (int c = 0; c < 4; ++c) {
        m[c] = 0.0 - m[c]; /* 0 - x: a zero stays +0 */
        m[4 + c] = 0.0 - m[4 + c];
    }
}

/* ---- header text ------------------------------------------------------------------------------ */

hv_status scan_head(const char *path, const uint8_t *mem, size_t size, size_t max, char **text, size_t *len)
{
    char *t = hv_malloc(max + 1);
    if (!t) return HV_ERR_NOMEM;
    size_t n;
    if (mem) {
        n = HV_MIN(size, max);
        memcpy(t, mem, n);
    } else {
        FILE *fp = fopen(path, "rb");
        if (!fp) {
            free(t);
            return hv_error_set(HV_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
        }
        n = fread(t, 1, max, fp);
        int bad = ferror(fp);
        fclose(fp);
        if (bad) {
            free(t);
            return hv_error_set(HV_ERR_IO, "%s: read error", path);
        }
    }
    t[n] = 0;
    *text = t;
    *len = n;
    return HV_OK;
}

int scan_numbers(const char *s, double *v, int n, const char **end)
{
    int k = 0;
    const char *p = s;
    while (k < n) {
        while (*p == ' ' || *p == '\t' || *p == ',' || *p == '(' || *p == ')') ++p;
        if (!*p || *p == '\n' || *p == '\r') break;
        char *e;
        double d = strtod(p, &e);
        if (e == p || !isfinite(d)) break;
        v[k++] = d;
        p = e;
    }
    if (end) *end = p;
    return k;
}

char *scan_sibling(const char *header_path, const char *file)
{
    if (file[0] == '/') return hv_strdup(file);
    const char *slash = strrchr(header_path, '/');
    size_t d = slash ? (size_t)(slash - header_path + 1) : 0;
    size_t n = strlen(file);
    char *p = hv_malloc(d + n + 1);
    if (!p) return NULL;
    memcpy(p, header_path, d);
    memcpy(p + d, file, n + 1);
    return p;
}

/* ---- the handle -------------------------------------------------------------------------------- */

static int ext_is(const char *path, const char *ext) { return hv_has_extension(path, ext); }

int hv_scan_path_is_scan(const char *path)
{
    if (!path) return 0;
    static const char *const k[] = {".nii", ".nii.gz", ".nrrd", ".nhdr", ".mha", ".mhd"};
    for (size_t i = 0; i < HV_COUNT(k); ++i)
        if (ext_is(path, k[i])) return 1;
    /* a directory is a DICOM series, unless it is named as a mesh or model would be */
    static const char *const not_scan[] = {".stl", ".3mf", ".obj", ".ply", ".vdb", ".vti", ".vtu"};
    for (size_t i = 0; i < HV_COUNT(not_scan); ++i)
        if (ext_is(path, not_scan[i])) return 0;
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

typedef enum { K_NONE, K_NIFTI, K_NRRD, K_MHA, K_DICOM } kind;

static kind kind_of(const char *name, int is_dir)
{
    if (is_dir) return K_DICOM;
    if (ext_is(name, ".nii") || ext_is(name, ".nii.gz")) return K_NIFTI;
    if (ext_is(name, ".nrrd") || ext_is(name, ".nhdr")) return K_NRRD;
    if (ext_is(name, ".mha") || ext_is(name, ".mhd")) return K_MHA;
    if (ext_is(name, ".dcm")) return K_DICOM;
    return K_NONE;
}

static hv_status scan_new(const char *name, hv_scan **out)
{
    hv_scan *s = hv_calloc(1, sizeof *s);
    if (!s) return HV_ERR_NOMEM;
    s->name = hv_strdup(name);
    if (!s->name) {
        free(s);
        return HV_ERR_NOMEM;
    }
    s->info.slope = 1;
    s->info.files = 1;
    *out = s;
    return HV_OK;
}

static hv_status read_any(const char *path, const uint8_t *mem, size_t size, const char *name,
                          const hv_scan_options *opts, hv_scan **out)
{
    *out = NULL;
    if (opts) {
        hv_status st = hv_options_check(hv_scan_option_set(), opts);
        if (st != HV_OK) return st;
    }
    struct stat st_;
    int is_dir = path && stat(path, &st_) == 0 && S_ISDIR(st_.st_mode);
    if (path && !is_dir && stat(path, &st_) != 0)
        return hv_error_set(HV_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    kind k = kind_of(name, is_dir);
    if (k == K_NONE)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: not a volume hovox reads (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, "
                                              "or a directory of DICOM slices)", name);
    hv_scan *s;
    hv_status st = scan_new(name, &s);
    if (st != HV_OK) return st;
    if (path) hv_input_note(path);
    switch (k) {
    case K_NIFTI: st = scan_read_nifti(s, path, mem, size, opts); break;
    case K_NRRD: st = scan_read_nrrd(s, path, mem, size, opts); break;
    case K_MHA: st = scan_read_metaimage(s, path, mem, size, opts); break;
    default: st = path ? scan_read_dicom_dir(s, path, opts) : scan_read_dicom_mem(s, mem, size, opts); break;
    }
    if (st == HV_OK) st = scan_finish(s);
    if (st != HV_OK) {
        hv_scan_destroy(s);
        return st;
    }
    *out = s;
    return HV_OK;
}

hv_status hv_scan_load(const char *path, const hv_scan_options *opts, hv_scan **out)
{
    if (!path || !out) return hv_error_set(HV_ERR_INVALID, "hv_scan_load: NULL argument");
    return read_any(path, NULL, 0, path, opts, out);
}

hv_status hv_scan_parse(const void *data, size_t size, const char *name, const hv_scan_options *opts, hv_scan **out)
{
    if ((!data && size) || !name || !out) return hv_error_set(HV_ERR_INVALID, "hv_scan_parse: NULL argument");
    static const uint8_t empty[1];
    return read_any(NULL, data ? data : empty, size, name, opts, out);
}

void hv_scan_destroy(hv_scan *scan)
{
    if (!scan) return;
    free(scan->data);
    free(scan->name);
    free(scan);
}

void hv_scan_dims(const hv_scan *scan, size_t dims[3]) { memcpy(dims, scan->dims, sizeof scan->dims); }
const float *hv_scan_data(const hv_scan *scan) { return scan->data; }
void hv_scan_affine(const hv_scan *scan, double m[12]) { memcpy(m, scan->m, sizeof scan->m); }
const hv_scan_info *hv_scan_get_info(const hv_scan *scan) { return &scan->info; }
const char *hv_scan_name(const hv_scan *scan) { return scan->name; }

hv_status hv_scan_transform(hv_scan *scan, const double a[12])
{
    double m[12];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            m[4 * r + c] = a[4 * r] * scan->m[c] + a[4 * r + 1] * scan->m[4 + c] + a[4 * r + 2] * scan->m[8 + c] +
                           (c == 3 ? a[4 * r + 3] : 0.0);
    double keep[12];
    memcpy(keep, scan->m, sizeof keep);
    memcpy(scan->m, m, sizeof m);
    hv_status st = scan_check_affine(scan, "the placed index-to-world transform");
    if (st != HV_OK) {
        memcpy(scan->m, keep, sizeof keep);
        char msg[512];
        snprintf(msg, sizeof msg, "%s", hv_last_error()); /* a value the caller gave, not the file's */
        return hv_error_set(HV_ERR_INVALID, "%s", msg);
    }
    return HV_OK;
}

hv_status hv_scan_labels_parse(const char *text, int32_t **labels, size_t *count)
{
    *labels = NULL;
    *count = 0;
    size_t cap = 0;
    for (const char *p = text; *p;) {
        char *e;
        errno = 0;
        long long v = strtoll(p, &e, 10);
        if (e == p || errno || v < INT32_MIN || v > INT32_MAX || (*e && (*e != ',' || !e[1])) || *count == 65536) {
            int too_many = *count == 65536;
            free(*labels);
            *labels = NULL;
            *count = 0;
            return too_many ? hv_error_option(HV_ERR_INVALID, "{labels} must name at most 65536 labels")
                                   : hv_error_option(HV_ERR_INVALID, "{labels} must be integers A,B,..., got '%s'", text);
        }
        if (hv_grow((void **)labels, &cap, *count + 1, sizeof **labels) != HV_OK) {
            free(*labels);
            *labels = NULL;
            *count = 0;
            return HV_ERR_NOMEM;
        }
        (*labels)[(*count)++] = (int32_t)v;
        p = *e ? e + 1 : e;
    }
    if (!*count) return hv_error_option(HV_ERR_INVALID, "{labels} must name at least one label");
    return HV_OK;
}

/* ---- reports ------------------------------------------------------------------------------------ */

void hv_scan_geometry(const hv_scan *scan, double spacing[3], char axes[4], double lo[3], double hi[3])
{
    const double *m = scan->m;
    for (int a = 0; a < 3; ++a) {
        double c[3] = {m[a], m[4 + a], m[8 + a]};
        spacing[a] = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        int best = 0;
        for (int r = 1; r < 3; ++r)
            if (fabs(c[r]) > fabs(c[best])) best = r;
        static const char pos[] = "RAS", neg[] = "LPI";
        axes[a] = c[best] >= 0 ? pos[best] : neg[best];
    }
    axes[3] = 0;
    /* the box of the voxel cells: corners at index -1/2 and n - 1/2 */
    for (int r = 0; r < 3; ++r) lo[r] = INFINITY, hi[r] = -INFINITY;
    for (int c = 0; c < 8; ++c) {
        double idx[3];
        for (int a = 0; a < 3; ++a) idx[a] = (c >> a & 1) ? (double)scan->dims[a] - 0.5 : -0.5;
        for (int r = 0; r < 3; ++r) {
            double w = m[4 * r] * idx[0] + m[4 * r + 1] * idx[1] + m[4 * r + 2] * idx[2] + m[4 * r + 3];
            lo[r] = HV_MIN(lo[r], w);
            hi[r] = HV_MAX(hi[r], w);
        }
    }
}
