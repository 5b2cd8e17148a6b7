/* src/io/scan/nifti.c - NIfTI-1 and NIfTI-2 single files (.nii, and .nii.gz through zlib), after
 * the NIfTI-1 header (nifti1.h, NIfTI DFWG 2004) and NIfTI-2 (nifti2.h, 2011): either byte
 * order, one 3-D volume of a real sample type, scl_slope/scl_inter applied, xyzt_units to mm.
 * Orientation (nifti1.h "method 3, 2, 1"): the sform when sform_code > 0, else the qform
 * (quaternion, qfac in pixdim[0]) when qform_code > 0, else pixdim alone; NIfTI's world is RAS. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/scan/scan_internal.h"

#define N1_SIZE 348
#define N2_SIZE 540

typedef struct nhdr {
    int version, big;
    int64_t dim[8];
    int datatype, bitpix;
    double pixdim[8], vox_offset, slope, inter;
    int qform_code, sform_code, units;
    double quatern[3], qoffset[3], srow[12];
} nhdr;

static uint64_t get(const uint8_t *h, size_t off, size_t n, int big)
{
    uint64_t v = 0;
    for (size_t k = 0; k < n; ++k) v |= (uint64_t)h[off + (big ? n - 1 - k : k)] << (8 * k);
    return v;
}
static int16_t g16(const uint8_t *h, size_t off, int big) { return (int16_t)get(h, off, 2, big); }
static int32_t g32(const uint8_t *h, size_t off, int big) { return (int32_t)get(h, off, 4, big); }
static int64_t g64(const uint8_t *h, size_t off, int big) { return (int64_t)get(h, off, 8, big); }
static double gf(const uint8_t *h, size_t off, int big)
{
    uint32_t u = (uint32_t)get(h, off, 4, big);
    float f;
    memcpy(&f, &u, 4);
    return f;
}
static double gd(const uint8_t *h, size_t off, int big)
{
    uint64_t u = get(h, off, 8, big);
    double d;
    memcpy(&d, &u, 8);
    return d;
}

static void parse1(const uint8_t *h, int big, nhdr *n)
{
    n->version = 1;
    n->big = big;
    for (int i = 0; i < 8; ++i) n->dim[i] = g16(h, 40 + 2 * (size_t)i, big);
    n->datatype = g16(h, 70, big);
    n->bitpix = g16(h, 72, big);
    for (int i = 0; i < 8; ++i) n->pixdim[i] = gf(h, 76 + 4 * (size_t)i, big);
    n->vox_offset = gf(h, 108, big);
    n->slope = gf(h, 112, big);
    n->inter = gf(h, 116, big);
    n->units = h[123] & 7;
    n->qform_code = g16(h, 252, big);
    n->sform_code = g16(h, 254, big);
    for (int i = 0; i < 3; ++i) {
        n->quatern[i] = gf(h, 256 + 4 * (size_t)i, big);
        n->qoffset[i] = gf(h, 268 + 4 * (size_t)i, big);
    }
    for (int i = 0; i < 12; ++i) n->srow[i] = gf(h, 280 + 4 * (size_t)i, big);
}

static void parse2(const uint8_t *h, int big, nhdr *n)
{
    n->version = 2;
    n->big = big;
    n->datatype = g16(h, 12, big);
    n->bitpix = g16(h, 14, big);
    for (int i = 0; i < 8; ++i) n->dim[i] = g64(h, 16 + 8 * (size_t)i, big);
    for (int i = 0; i < 8; ++i) n->pixdim[i] = gd(h, 104 + 8 * (size_t)i, big);
    n->vox_offset = (double)g64(h, 168, big);
    n->slope = gd(h, 176, big);
    n->inter = gd(h, 184, big);
    n->qform_code = g32(h, 344, big);
    n->sform_code = g32(h, 348, big);
    for (int i = 0; i < 3; ++i) {
        n->quatern[i] = gd(h, 352 + 8 * (size_t)i, big);
        n->qoffset[i] = gd(h, 376 + 8 * (size_t)i, big);
    }
    for (int i = 0; i < 12; ++i) n->srow[i] = gd(h, 400 + 8 * (size_t)i, big);
    n->units = g32(h, 500, big) & 7;
}

static scan_type type_of(int datatype)
{
    switch (datatype) {
    case 2: return SCAN_U8;
    case 4: return SCAN_I16;
    case 8: return SCAN_I32;
    case 16: return SCAN_F32;
    case 64: return SCAN_F64;
    case 256: return SCAN_I8;
    case 512: return SCAN_U16;
    case 768: return SCAN_U32;
    case 1024: return SCAN_I64;
    case 1280: return SCAN_U64;
    default: return SCAN_NONE;
    }
}

static const char *code_name(int code)
{
    switch (code) {
    case 1: return "scanner";
    case 2: return "aligned";
    case 3: return "Talairach";
    case 4: return "MNI 152";
    case 5: return "template";
    default: return "unknown";
    }
}

/* nifti1.h method 2: the quaternion (b, c, d; a from unit length) times pixdim, qfac in pixdim[0]. */
static void qform(const nhdr *n, double m[12])
{
    double b = n->quatern[0], c = n->quatern[1], d = n->quatern[2];
    double a = 1.0 - (b * b + c * c + d * d);
    if (a < 1e-7) { /* a 180 degree turn: normalise (b, c, d) as nifti_quatern_to_mat44 does */
        double r = sqrt(b * b + c * c + d * d);
        if (r > 0) b /= r, c /= r, d /= r;
        a = 0;
    } else {
        a = sqrt(a);
    }
    double R[9] = {a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c),
                   2 * (b * c + a * d), a * a + c * c - b * b - d * d, 2 * (c * d - a * b),
                   2 * (b * d - a * c), 2 * (c * d + a * b), a * a + d * d - c * c - b * b};
    double qfac = n->pixdim[0] < 0 ? -1 : 1;
    double s[3] = {n->pixdim[1], n->pixdim[2], n->pixdim[3] * qfac};
    for (int r = 0; r < 3; ++r) {
        for (int k = 0; k < 3; ++k) m[4 * r + k] = R[3 * r + k] * s[k];
        m[4 * r + 3] = n->qoffset[r];
    }
}

static hv_status check_header(hv_scan *scan, const nhdr *n, scan_type *t, size_t dims[3])
{
    const char *name = scan->name;
    int64_t nd = n->dim[0];
    if (nd < 1 || nd > 7)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: dim[0] is %lld, not a number of dimensions in 1..7", name,
                            (long long)nd);
    for (int i = 1; i <= 7; ++i) {
        int64_t v = i <= nd ? n->dim[i] : 1;
        if (v < 1 || v > ((int64_t)1 << 31))
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: dim[%d] is %lld, not a size", name, i, (long long)v);
        if (i > 3 && v != 1)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: dim[%d] is %lld: a series of volumes; hovox reads one "
                                "3-D volume", name, i, (long long)v);
        if (i <= 3) dims[i - 1] = (size_t)v;
    }
    if ((double)dims[0] * (double)dims[1] * (double)dims[2] > 1e15)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: %zu x %zu x %zu samples is not a volume", name, dims[0],
                            dims[1], dims[2]);
    *t = type_of(n->datatype);
    if (*t == SCAN_NONE)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: datatype %d is not a real scalar type hovox reads (uint8, "
                            "int8, int16, uint16, int32, uint32, int64, uint64, float32, float64)", name, n->datatype);
    if ((size_t)n->bitpix != 8 * scan_type_size(*t))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: bitpix %d does not match datatype %s", name, n->bitpix,
                            scan_type_name(*t));
    double hs = n->version == 1 ? N1_SIZE : N2_SIZE;
    if (!isfinite(n->vox_offset) || n->vox_offset < hs || n->vox_offset > 1e15 || n->vox_offset != floor(n->vox_offset))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: vox_offset %g is not a byte offset after the header", name,
                            n->vox_offset);
    return HV_OK;
}

static hv_status orientation(hv_scan *scan, const nhdr *n)
{
    double unit = n->units == 1 ? 1000.0 : n->units == 3 ? 0.001 : 1.0;
    if (n->sform_code > 0) {
        memcpy(scan->m, n->srow, sizeof scan->m);
        snprintf(scan->space, sizeof scan->space, "sform (%s)", code_name(n->sform_code));
    } else {
        for (int i = 1; i <= 3; ++i)
            if (!isfinite(n->pixdim[i]) || !(n->pixdim[i] > 0))
                return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: pixdim[%d] is %g, not a voxel size", scan->name, i,
                                    n->pixdim[i]);
        if (n->qform_code > 0) {
            for (int i = 0; i < 3; ++i)
                if (!isfinite(n->quatern[i]) || !isfinite(n->qoffset[i]) || fabs(n->quatern[i]) > 1.0 + 1e-6)
                    return hv_error_set(HV_ERR_BAD_INPUT, "%s: header: the qform quaternion (%g, %g, %g) is not a rotation",
                                        scan->name, n->quatern[0], n->quatern[1], n->quatern[2]);
            qform(n, scan->m);
            snprintf(scan->space, sizeof scan->space, "qform (%s)", code_name(n->qform_code));
        } else {
            memset(scan->m, 0, sizeof scan->m);
            for (int i = 0; i < 3; ++i) scan->m[5 * i] = n->pixdim[i + 1];
            snprintf(scan->space, sizeof scan->space, "pixdim only (no sform or qform)");
        }
    }
    for (int i = 0; i < 12; ++i) scan->m[i] *= unit;
    return scan_check_affine(scan, n->sform_code > 0 ? "header: the sform" : "header: the qform");
}

hv_status scan_read_nifti(hv_scan *scan, const char *path, const uint8_t *mem, size_t size,
                          const hv_scan_options *opts)
{
    scan_src s;
    hv_status st;
    if (path) {
        st = scan_src_open_file(&s, path, scan->name, 0);
        if (st != HV_OK) return st;
    } else {
        scan_src_open_mem(&s, mem, size, scan->name, 0);
    }
    uint8_t h[N2_SIZE];
    size_t got = 0;
    /* gzip by its magic bytes, whatever the name says */
    st = scan_src_read(&s, h, 2, &got);
    if (st == HV_OK && got == 2 && h[0] == 0x1f && h[1] == 0x8b) {
        s.pos = 0;
        if (s.fp && fseeko(s.fp, 0, SEEK_SET) != 0) st = hv_error_set(HV_ERR_IO, "%s: cannot seek", scan->name);
        s.out = 0;
        if (st == HV_OK) st = scan_src_inflate(&s);
        if (st == HV_OK) st = scan_src_read(&s, h, 4, &got);
        snprintf(scan->encoding, sizeof scan->encoding, "gzip");
    } else if (st == HV_OK && got == 2) {
        size_t g2;
        st = scan_src_read(&s, h + 2, 2, &g2);
        got += g2;
        snprintf(scan->encoding, sizeof scan->encoding, "raw");
    }
    if (st != HV_OK) goto done;
    if (got < 4) {
        st = hv_error_set(HV_ERR_BAD_INPUT, "%s: %zu bytes: too short for a NIfTI header", scan->name, got);
        goto done;
    }
    uint32_t le = (uint32_t)get(h, 0, 4, 0), be = (uint32_t)get(h, 0, 4, 1);
    int version = le == N1_SIZE || be == N1_SIZE ? 1 : le == N2_SIZE || be == N2_SIZE ? 2 : 0;
    if (!version) {
        st = hv_error_set(HV_ERR_BAD_INPUT, "%s: not a NIfTI file (sizeof_hdr %u, neither 348 nor 540)", scan->name, le);
        goto done;
    }
    int big = le != (version == 1 ? N1_SIZE : N2_SIZE);
    size_t hs = version == 1 ? N1_SIZE : N2_SIZE, g;
    st = scan_src_read(&s, h + 4, hs - 4, &g);
    if (st != HV_OK) goto done;
    if (g < hs - 4) {
        st = hv_error_set(HV_ERR_BAD_INPUT, "%s: truncated: the NIfTI-%d header ends after %zu of %zu bytes", scan->name,
                          version, g + 4, hs);
        goto done;
    }
    nhdr n;
    memset(&n, 0, sizeof n);
    if (version == 1) {
        if (memcmp(h + 344, "n+1", 4) != 0) {
            st = hv_error_set(HV_ERR_BAD_INPUT, memcmp(h + 344, "ni1", 4) == 0
                                                    ? "%s: a NIfTI-1 header of a .hdr/.img pair (magic 'ni1'); hovox reads single .nii files"
                                                    : "%s: the NIfTI-1 magic is not 'n+1'", scan->name);
            goto done;
        }
        parse1(h, big, &n);
    } else {
        if (memcmp(h + 4, "n+2\0\r\n\032\n", 8) != 0) {
            st = hv_error_set(HV_ERR_BAD_INPUT, "%s: the NIfTI-2 magic is not 'n+2' (a .hdr/.img pair, or damaged)",
                              scan->name);
            goto done;
        }
        parse2(h, big, &n);
    }
    scan->info.format = version == 1 ? HV_SCAN_NIFTI1 : HV_SCAN_NIFTI2;
    scan->info.format_name = version == 1 ? "NIfTI-1" : "NIfTI-2";
    scan_type t = SCAN_NONE;
    size_t dims[3] = {0, 0, 0};
    st = check_header(scan, &n, &t, dims);
    if (st == HV_OK) st = orientation(scan, &n);
    if (st != HV_OK) goto done;
    double slope = n.slope, inter = n.inter;
    if (!isfinite(slope) || slope == 0 || !isfinite(inter)) slope = 1, inter = 0; /* nifti1.h: 0 means none */
    scan->info.slope = slope;
    scan->info.intercept = inter;
    snprintf(scan->sample_type, sizeof scan->sample_type, "%s", scan_type_name(t));
    /* skip the extensions to vox_offset */
    uint64_t skip = (uint64_t)n.vox_offset - hs;
    uint8_t junk[4096];
    while (skip && st == HV_OK) {
        size_t k = (size_t)HV_MIN(skip, (uint64_t)sizeof junk);
        st = scan_src_read(&s, junk, k, &g);
        if (st == HV_OK && g < k)
            st = hv_error_set(HV_ERR_BAD_INPUT, "%s: truncated: the file ends before vox_offset %.0f", scan->name,
                              n.vox_offset);
        skip -= k;
    }
    if (st != HV_OK) goto done;
    uint64_t need = (uint64_t)dims[0] * dims[1] * dims[2] * scan_type_size(t);
    if (!s.inflating && scan_src_left(&s) < need) {
        st = hv_error_set(HV_ERR_BAD_INPUT, "%s: the header says %zu x %zu x %zu %s samples (%llu bytes) from byte %.0f; "
                          "the file holds %llu", scan->name, dims[0], dims[1], dims[2], scan_type_name(t),
                          (unsigned long long)need, n.vox_offset, (unsigned long long)scan_src_left(&s));
        goto done;
    }
    st = scan_alloc(scan, dims, opts);
    if (st == HV_OK) st = scan_read_samples(&s, t, big, slope, inter, scan->data, dims[0] * dims[1] * dims[2]);
    if (st == HV_OK) st = scan_src_end(&s);
done:
    scan_src_close(&s);
    return st;
}
