/* src/io/scan/dicom.c - DICOM series: a directory of single-frame slices of one series (DICOM
 * PS3.5 data encoding: the Part 10 file meta group, explicit and implicit VR little endian;
 * sequences of defined and undefined length skipped; compressed transfer syntaxes refused).
 * PS3.3 C.7.6.2 image plane: slices sorted by ImagePositionPatient along the normal of
 * ImageOrientationPatient, equal steps required (a gap or a repeated position is refused), the
 * affine from PixelSpacing and the positions (LPS, made RAS); PS3.3 C.11.1 modality LUT: the
 * rescale slope and intercept of each slice give the values (Hounsfield units for CT). */
#include <dirent.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "io/scan/scan_internal.h"

#define BAD(...) hv_error_set(HV_ERR_BAD_INPUT, __VA_ARGS__)
#define MAX_FILES 100000
#define MAX_FILE_BYTES ((size_t)1 << 30)

typedef struct dslice {
    char *path;
    char series[68], modality[20], rescale_type[20], photometric[20], syntax[68];
    uint32_t rows, cols;
    unsigned bits_alloc, bits_stored, pixrep, spp, frames;
    double ps[2], ipp[3], iop[6], slope, inter, d;
    int has_ps, has_ipp, has_iop;
    uint64_t pix_off, pix_len;
} dslice;

typedef struct rd {
    const uint8_t *p;
    size_t size, pos;
    int explicit_vr;
    const char *name;
} rd;

typedef struct el {
    uint16_t g, e;
    char vr[3];
    uint32_t len; /* 0xFFFFFFFF: undefined */
    size_t at;    /* value offset */
} el;

static uint16_t u16(const uint8_t *p) { return (uint16_t)(p[0] | p[1] << 8); }
static uint32_t u32(const uint8_t *p) { return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24; }

static int long_vr(const char *vr)
{
    static const char *const k[] = {"OB", "OD", "OF", "OL", "OV", "OW", "SQ", "UC", "UN", "UR", "UT", "SV", "UV"};
    for (size_t i = 0; i < HV_COUNT(k); ++i)
        if (vr[0] == k[i][0] && vr[1] == k[i][1]) return 1;
    return 0;
}

/* The next element's header; the position is left at its value. 0 at the end. */
static hv_status next(rd *r, el *e, int *got)
{
    *got = 0;
    if (r->pos == r->size) return HV_OK;
    if (r->size - r->pos < 8) return BAD("%s: truncated: an element header at byte %zu is cut short", r->name, r->pos);
    const uint8_t *p = r->p + r->pos;
    e->g = u16(p);
    e->e = u16(p + 2);
    e->vr[0] = e->vr[2] = 0;
    if (e->g == 0xFFFE || !r->explicit_vr) {
        e->len = u32(p + 4);
        r->pos += 8;
    } else {
        e->vr[0] = (char)p[4];
        e->vr[1] = (char)p[5];
        e->vr[2] = 0;
        if (e->vr[0] < 'A' || e->vr[0] > 'Z' || e->vr[1] < 'A' || e->vr[1] > 'Z')
            return BAD("%s: byte %zu: element (%04X,%04X) has no value representation (bytes %02X %02X)", r->name, r->pos,
                       e->g, e->e, p[4], p[5]);
        if (long_vr(e->vr)) {
            if (r->size - r->pos < 12) return BAD("%s: truncated: an element header at byte %zu is cut short", r->name, r->pos);
            e->len = u32(p + 8);
            r->pos += 12;
        } else {
            e->len = u16(p + 6);
            r->pos += 8;
        }
    }
    e->at = r->pos;
    if (e->len != 0xFFFFFFFFu && e->len > r->size - r->pos)
        return BAD("%s: truncated: element (%04X,%04X) at byte %zu holds %u bytes, %zu remain", r->name, e->g, e->e,
                   r->pos - 8, e->len, r->size - r->pos);
    *got = 1;
    return HV_OK;
}

/* Skip the value of an element of undefined length (a sequence, or an item): items up to the
 * sequence delimiter, elements up to the item delimiter. */
static hv_status skip_undefined(rd *r, int depth, int in_item)
{
    if (depth > 32) return BAD("%s: byte %zu: sequences nested more than 32 deep", r->name, r->pos);
    for (;;) {
        el e;
        int got;
        hv_status st = next(r, &e, &got);
        if (st != HV_OK) return st;
        if (!got) return BAD("%s: truncated: a sequence of undefined length has no end", r->name);
        if (e.g == 0xFFFE && e.e == (in_item ? 0xE00D : 0xE0DD)) return HV_OK;
        if (e.g == 0xFFFE && e.e != 0xE000)
            return BAD("%s: byte %zu: delimiter (FFFE,%04X) out of place", r->name, e.at - 8, e.e);
        if (e.len == 0xFFFFFFFFu) {
            st = skip_undefined(r, depth + 1, e.g == 0xFFFE && e.e == 0xE000);
            if (st != HV_OK) return st;
        } else {
            r->pos += e.len;
        }
    }
}

static void str_value(const rd *r, const el *e, char *out, size_t cap)
{
    size_t n = HV_MIN((size_t)e->len, cap - 1);
    memcpy(out, r->p + e->at, n);
    out[n] = 0;
    while (n && (out[n - 1] == ' ' || out[n - 1] == 0)) out[--n] = 0;
    size_t s = 0;
    while (out[s] == ' ') ++s;
    memmove(out, out + s, n - s + 1);
}

/* n decimal strings separated by '\'. */
static hv_status ds_values(const rd *r, const el *e, double *v, int n)
{
    char buf[256];
    str_value(r, e, buf, sizeof buf);
    char *p = buf;
    for (int i = 0; i < n; ++i) {
        char *end;
        v[i] = strtod(p, &end);
        if (end == p || !isfinite(v[i]))
            return BAD("%s: element (%04X,%04X) '%s' does not hold %d decimal numbers", r->name, e->g, e->e, buf, n);
        while (*end == ' ') ++end;
        if (i + 1 < n) {
            if (*end != '\\') return BAD("%s: element (%04X,%04X) '%s' does not hold %d decimal numbers", r->name, e->g, e->e, buf, n);
            ++end;
        }
        p = end;
    }
    return HV_OK;
}

static unsigned us_value(const rd *r, const el *e) { return e->len >= 2 ? u16(r->p + e->at) : 0; }

/* Parse one Part 10 file's header (not the pixels). */
static hv_status parse_slice(const uint8_t *data, size_t size, const char *name, dslice *s)
{
    rd r = {data, size, 0, 1, name};
    memset(s, 0, sizeof *s);
    s->slope = 1;
    s->spp = 1;
    s->frames = 1;
    if (size >= 132 && memcmp(data + 128, "DICM", 4) == 0) {
        r.pos = 132;
        /* the file meta group: explicit VR little endian */
        for (;;) {
            if (r.size - r.pos < 8 || u16(data + r.pos) != 0x0002) break;
            el e;
            int got;
            hv_status st = next(&r, &e, &got);
            if (st != HV_OK) return st;
            if (e.len == 0xFFFFFFFFu) return BAD("%s: byte %zu: a file meta element of undefined length", name, e.at);
            if (e.e == 0x0010) str_value(&r, &e, s->syntax, sizeof s->syntax);
            r.pos += e.len;
        }
        if (!s->syntax[0]) return BAD("%s: the file meta group names no transfer syntax (0002,0010)", name);
        if (strcmp(s->syntax, "1.2.840.10008.1.2") == 0) r.explicit_vr = 0;
        else if (strcmp(s->syntax, "1.2.840.10008.1.2.1") == 0) r.explicit_vr = 1;
        else
            return hv_error_set(HV_ERR_UNSUPPORTED, "%s: transfer syntax %s is not read (hovox reads uncompressed little "
                                "endian slices: convert the series, e.g. with gdcmconv --raw)", name, s->syntax);
    } else if (size >= 8 && u16(data) == 0x0008 && u16(data + 2) < 0x0100) {
        r.explicit_vr = 0; /* no preamble: an old implicit VR little endian file */
        snprintf(s->syntax, sizeof s->syntax, "1.2.840.10008.1.2");
    } else {
        return BAD("%s: not a DICOM file (no 'DICM' at byte 128)", name);
    }
    for (;;) {
        el e;
        int got;
        hv_status st = next(&r, &e, &got);
        if (st != HV_OK) return st;
        if (!got) break;
        uint32_t tag = (uint32_t)e.g << 16 | e.e;
        if (tag == 0x7FE00010u) {
            if (e.len == 0xFFFFFFFFu) return hv_error_set(HV_ERR_UNSUPPORTED, "%s: encapsulated (compressed) pixel data is not read", name);
            s->pix_off = e.at;
            s->pix_len = e.len;
            return HV_OK;
        }
        if (e.len == 0xFFFFFFFFu) {
            st = skip_undefined(&r, 0, e.g == 0xFFFE && e.e == 0xE000);
            if (st != HV_OK) return st;
            continue;
        }
        switch (tag) {
        case 0x00080060u: str_value(&r, &e, s->modality, sizeof s->modality); break;
        case 0x0020000Eu: str_value(&r, &e, s->series, sizeof s->series); break;
        case 0x00200032u: st = ds_values(&r, &e, s->ipp, 3); s->has_ipp = 1; break;
        case 0x00200037u: st = ds_values(&r, &e, s->iop, 6); s->has_iop = 1; break;
        case 0x00280002u: s->spp = us_value(&r, &e); break;
        case 0x00280004u: str_value(&r, &e, s->photometric, sizeof s->photometric); break;
        case 0x00280008u: {
            char b[16];
            str_value(&r, &e, b, sizeof b);
            s->frames = (unsigned)atoi(b);
            break;
        }
        case 0x00280010u: s->rows = us_value(&r, &e); break;
        case 0x00280011u: s->cols = us_value(&r, &e); break;
        case 0x00280030u: st = ds_values(&r, &e, s->ps, 2); s->has_ps = 1; break;
        case 0x00280100u: s->bits_alloc = us_value(&r, &e); break;
        case 0x00280101u: s->bits_stored = us_value(&r, &e); break;
        case 0x00280103u: s->pixrep = us_value(&r, &e); break;
        case 0x00281052u: st = ds_values(&r, &e, &s->inter, 1); break;
        case 0x00281053u: st = ds_values(&r, &e, &s->slope, 1); break;
        case 0x00281054u: str_value(&r, &e, s->rescale_type, sizeof s->rescale_type); break;
        default: break;
        }
        if (st != HV_OK) return st;
        r.pos += e.len;
    }
    return BAD("%s: no pixel data (7FE0,0010)", name);
}

/* What one slice must be on its own. */
static hv_status check_slice(const dslice *s, const char *name)
{
    if (s->spp != 1) return BAD("%s: %u samples per pixel: hovox reads grey-scale slices", name, s->spp);
    if (s->photometric[0] && strcmp(s->photometric, "MONOCHROME1") && strcmp(s->photometric, "MONOCHROME2"))
        return BAD("%s: photometric interpretation %s: hovox reads MONOCHROME1/2 slices", name, s->photometric);
    if (s->frames > 1) return BAD("%s: %u frames: hovox reads series of single-frame slices", name, s->frames);
    if (!s->rows || !s->cols) return BAD("%s: %u rows and %u columns: no image", name, s->rows, s->cols);
    if (s->bits_alloc != 8 && s->bits_alloc != 16 && s->bits_alloc != 32)
        return BAD("%s: bits allocated %u: hovox reads 8, 16 or 32", name, s->bits_alloc);
    if (s->bits_stored == 0 || s->bits_stored > s->bits_alloc)
        return BAD("%s: bits stored %u does not fit bits allocated %u", name, s->bits_stored, s->bits_alloc);
    if (s->pixrep > 1) return BAD("%s: pixel representation %u is neither 0 nor 1", name, s->pixrep);
    uint64_t need = (uint64_t)s->rows * s->cols * (s->bits_alloc / 8);
    if (s->pix_len < need)
        return BAD("%s: the pixel data holds %llu bytes, %u x %u pixels of %u bits need %llu", name,
                   (unsigned long long)s->pix_len, s->cols, s->rows, s->bits_alloc, (unsigned long long)need);
    if (!isfinite(s->slope) || s->slope == 0) return BAD("%s: rescale slope %g", name, s->slope);
    if (s->has_ps && (!(s->ps[0] > 0) || !(s->ps[1] > 0) || s->ps[0] > 1e4 || s->ps[1] > 1e4))
        return BAD("%s: pixel spacing %g\\%g is not two sizes above 0", name, s->ps[0], s->ps[1]);
    return HV_OK;
}

static void decode(const uint8_t *p, const dslice *s, float *out)
{
    size_t n = (size_t)s->rows * s->cols, w = s->bits_alloc / 8;
    uint64_t mask = s->bits_stored >= 64 ? ~0ull : ((1ull << s->bits_stored) - 1);
    uint64_t sign = 1ull << (s->bits_stored - 1);
    for (size_t i = 0; i < n; ++i, p += w) {
        uint64_t u = w == 1 ? p[0] : w == 2 ? u16(p) : u32(p);
        u &= mask;
        double v = s->pixrep && (u & sign) ? (double)(int64_t)(u | ~mask) : (double)u;
        out[i] = (float)(v * s->slope + s->inter);
    }
}

static int cmp_d(const void *a, const void *b)
{
    double x = ((const dslice *)a)->d, y = ((const dslice *)b)->d;
    return x < y ? -1 : x > y;
}

static int cmp_str(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Check the slices agree, sort them and set the affine. */
static hv_status series_plan(hv_scan *scan, dslice *sl, size_t n)
{
    const char *nm = scan->name;
    dslice *a = &sl[0];
    for (size_t i = 0; i < n; ++i) {
        hv_status st = check_slice(&sl[i], sl[i].path ? hv_basename(sl[i].path) : nm);
        if (st != HV_OK) return hv_error_prefix(st, "%s: ", n > 1 || sl[i].path ? nm : "");
    }
    for (size_t i = 1; i < n; ++i) {
        const dslice *b = &sl[i];
        const char *bn = hv_basename(b->path);
        if (strcmp(a->series, b->series))
            return BAD("%s: two series: %s holds series %s, %s series %s (give one series' directory)", nm,
                       hv_basename(a->path), a->series[0] ? a->series : "(none)", bn, b->series[0] ? b->series : "(none)");
        if (a->rows != b->rows || a->cols != b->cols || a->bits_alloc != b->bits_alloc || a->pixrep != b->pixrep)
            return BAD("%s: mixed slices: %s is %u x %u of %u bits, %s %u x %u of %u bits", nm, hv_basename(a->path), a->cols,
                       a->rows, a->bits_alloc, bn, b->cols, b->rows, b->bits_alloc);
        if (!b->has_ipp || !b->has_iop || !a->has_ipp || !a->has_iop)
            return BAD("%s: %s has no image position or orientation (0020,0032/0037): the slices cannot be ordered", nm,
                       !b->has_ipp || !b->has_iop ? bn : hv_basename(a->path));
        for (int k = 0; k < 6; ++k)
            if (fabs(a->iop[k] - b->iop[k]) > 1e-4)
                return BAD("%s: mixed orientations: %s and %s differ in image orientation (0020,0037)", nm,
                           hv_basename(a->path), bn);
        if (a->has_ps != b->has_ps || fabs(a->ps[0] - b->ps[0]) > 1e-6 * a->ps[0] || fabs(a->ps[1] - b->ps[1]) > 1e-6 * a->ps[1])
            return BAD("%s: mixed pixel spacings: %s %g\\%g, %s %g\\%g", nm, hv_basename(a->path), a->ps[0], a->ps[1], bn,
                       b->ps[0], b->ps[1]);
    }
    double row[3] = {1, 0, 0}, col[3] = {0, 1, 0}, nrm[3] = {0, 0, 1};
    if (a->has_iop) {
        memcpy(row, a->iop, sizeof row);
        memcpy(col, a->iop + 3, sizeof col);
        double lr = sqrt(dot(row, row)), lc = sqrt(dot(col, col));
        if (fabs(lr - 1) > 1e-3 || fabs(lc - 1) > 1e-3 || fabs(dot(row, col)) > 1e-3)
            return BAD("%s: image orientation %g\\%g\\%g\\%g\\%g\\%g is not two orthogonal unit vectors", nm, row[0], row[1],
                       row[2], col[0], col[1], col[2]);
        nrm[0] = row[1] * col[2] - row[2] * col[1];
        nrm[1] = row[2] * col[0] - row[0] * col[2];
        nrm[2] = row[0] * col[1] - row[1] * col[0];
    }
    for (size_t i = 0; i < n; ++i) sl[i].d = dot(sl[i].ipp, nrm);
    qsort(sl, n, sizeof *sl, cmp_d);
    double step[3] = {nrm[0], nrm[1], nrm[2]};
    if (n > 1) {
        double *steps = hv_malloc_array(n - 1, sizeof *steps);
        if (!steps) return HV_ERR_NOMEM;
        for (size_t i = 0; i + 1 < n; ++i) steps[i] = sl[i + 1].d - sl[i].d;
        double lo = steps[0], hi = steps[0];
        size_t at = 0;
        for (size_t i = 0; i + 1 < n; ++i) {
            if (steps[i] < lo) lo = steps[i];
            if (steps[i] > hi) hi = steps[i], at = i;
        }
        double total = sl[n - 1].d - sl[0].d, mean = total / (double)(n - 1);
        free(steps);
        if (lo < 1e-4 * HV_MAX(1.0, fabs(mean))) {
            for (size_t i = 0; i + 1 < n; ++i)
                if (sl[i + 1].d - sl[i].d == lo)
                    return BAD("%s: %s and %s lie at the same position (%g mm along the normal)", nm, hv_basename(sl[i].path),
                               hv_basename(sl[i + 1].path), sl[i].d);
        }
        if (hi - lo > 0.01 * mean + 1e-3)
            return BAD("%s: a gap in the series: %g mm between %s and %s where the other slices are %g mm apart", nm, hi,
                       hv_basename(sl[at].path), hv_basename(sl[at + 1].path), lo);
        for (int k = 0; k < 3; ++k) step[k] = (sl[n - 1].ipp[k] - sl[0].ipp[k]) / (double)(n - 1);
        for (size_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k)
                if (fabs(sl[i].ipp[k] - (sl[0].ipp[k] + (double)i * step[k])) > 0.05 * mean + 1e-3)
                    return BAD("%s: %s lies off the line of the other slices' positions", nm, hv_basename(sl[i].path));
    } else if (a->has_ps) {
        for (int k = 0; k < 3; ++k) step[k] = nrm[k] * a->ps[0]; /* one slice: as thick as its pixels are wide */
    }
    double ps_r = a->has_ps ? a->ps[0] : 1, ps_c = a->has_ps ? a->ps[1] : 1;
    for (int r = 0; r < 3; ++r) {
        scan->m[4 * r + 0] = row[r] * ps_c;
        scan->m[4 * r + 1] = col[r] * ps_r;
        scan->m[4 * r + 2] = step[r];
        scan->m[4 * r + 3] = a->has_ipp ? sl[0].ipp[r] : 0;
    }
    scan_lps_to_ras(scan->m);
    snprintf(scan->space, sizeof scan->space, "%s", a->has_ipp ? "LPS (patient) -> RAS" : "no image position (taken as RAS at 0)");
    scan->info.format = HV_SCAN_DICOM;
    scan->info.format_name = "DICOM series";
    scan->info.files = n;
    scan->info.slope = a->slope;
    scan->info.intercept = a->inter;
    snprintf(scan->sample_type, sizeof scan->sample_type, "%s%u", a->pixrep ? "int" : "uint", a->bits_alloc);
    snprintf(scan->encoding, sizeof scan->encoding, "%s", strcmp(a->syntax, "1.2.840.10008.1.2") ? "explicit VR LE" : "implicit VR LE");
    if (a->rescale_type[0]) snprintf(scan->unit, sizeof scan->unit, "%s", a->rescale_type);
    else if (strcmp(a->modality, "CT") == 0) snprintf(scan->unit, sizeof scan->unit, "HU");
    return scan_check_affine(scan, "the slices' positions and orientation");
}

hv_status scan_read_dicom_mem(hv_scan *scan, const uint8_t *mem, size_t size, const hv_scan_options *opts)
{
    dslice s;
    hv_status st = parse_slice(mem, size, scan->name, &s);
    if (st == HV_OK) st = series_plan(scan, &s, 1);
    size_t dims[3] = {s.cols, s.rows, 1};
    if (st == HV_OK) st = scan_alloc(scan, dims, opts);
    if (st == HV_OK) decode(mem + s.pix_off, &s, scan->data);
    return st;
}

static void free_slices(dslice *sl, size_t n)
{
    for (size_t i = 0; i < n; ++i) free(sl[i].path);
    free(sl);
}

hv_status scan_read_dicom_dir(hv_scan *scan, const char *dir, const hv_scan_options *opts)
{
    DIR *d = opendir(dir);
    if (!d) return hv_error_set(HV_ERR_IO, "%s: cannot open the directory", dir);
    char **names = NULL;
    size_t n = 0, cap = 0;
    hv_status st = HV_OK;
    struct dirent *de;
    while ((de = readdir(d)) != NULL) {
        if (strcmp(de->d_name, "manifest.json") == 0) { /* hovox's own output, not a series */
            st = BAD("%s: a slice stack (it holds manifest.json), not a DICOM series: 'hovox view %s' shows it", dir,
                     dir);
            break;
        }
        if (de->d_name[0] == '.' || strcmp(de->d_name, "DICOMDIR") == 0) continue;
        size_t a = strlen(dir), b = strlen(de->d_name);
        int slash = a && dir[a - 1] == '/';
        char *p = hv_malloc(a + b + 2);
        if (p) {
            memcpy(p, dir, a);
            if (!slash) p[a++] = '/';
            memcpy(p + a, de->d_name, b + 1);
        }
        struct stat sb;
        if (!p) {
            st = HV_ERR_NOMEM;
            break;
        }
        if (stat(p, &sb) != 0 || !S_ISREG(sb.st_mode)) {
            free(p);
            continue;
        }
        if (n == MAX_FILES) {
            free(p);
            st = hv_error_set(HV_ERR_LIMIT, "%s: more than %d files", dir, MAX_FILES);
            break;
        }
        if ((st = hv_grow((void **)&names, &cap, n + 1, sizeof *names)) != HV_OK) {
            free(p);
            break;
        }
        names[n++] = p;
    }
    closedir(d);
    if (st == HV_OK && n == 0) st = BAD("%s: an empty directory: no DICOM slices", dir);
    dslice *sl = st == HV_OK ? hv_calloc(n, sizeof *sl) : NULL;
    if (st == HV_OK && !sl) st = HV_ERR_NOMEM;
    if (st == HV_OK) qsort(names, n, sizeof *names, cmp_str);
    for (size_t i = 0; i < n && st == HV_OK; ++i) {
        char *buf;
        size_t len;
        st = hv_read_file(names[i], MAX_FILE_BYTES, &buf, &len);
        if (st == HV_OK) {
            st = parse_slice((const uint8_t *)buf, len, names[i], &sl[i]);
            free(buf);
        }
        sl[i].path = names[i];
        names[i] = NULL;
        if (st == HV_OK) hv_input_note(sl[i].path);
        if (st == HV_OK && (i & 63) == 0 && hv_cancel_requested()) st = hv_error_set(HV_ERR_CANCELLED, "cancelled");
    }
    for (size_t i = 0; i < n; ++i) free(names[i]);
    free(names);
    if (st == HV_OK) st = series_plan(scan, sl, n);
    size_t dims[3] = {sl ? sl[0].cols : 0, sl ? sl[0].rows : 0, n};
    if (st == HV_OK) st = scan_alloc(scan, dims, opts);
    size_t plane = dims[0] * dims[1];
    for (size_t k = 0; k < n && st == HV_OK; ++k) {
        char *buf;
        size_t len;
        dslice again;
        st = hv_read_file(sl[k].path, MAX_FILE_BYTES, &buf, &len);
        if (st != HV_OK) break;
        /* read again: the file must still say what it said */
        st = parse_slice((const uint8_t *)buf, len, sl[k].path, &again);
        if (st == HV_OK && (again.pix_off != sl[k].pix_off || again.rows != sl[k].rows || again.cols != sl[k].cols))
            st = BAD("%s: changed while it was read", sl[k].path);
        if (st == HV_OK) decode((const uint8_t *)buf + again.pix_off, &again, scan->data + k * plane);
        free(buf);
        if (st == HV_OK && (k & 15) == 0 && hv_cancel_requested()) st = hv_error_set(HV_ERR_CANCELLED, "cancelled");
    }
    if (sl) free_slices(sl, n);
    return st;
}
