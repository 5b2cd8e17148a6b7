/* tests/io/scan/test_scan.c - the scan readers (src/io/scan) against independent writers: the head
 * phantom of tests/io/scan/make_phantom.py written by nibabel (NIfTI-1/2), pydicom (a DICOM
 * series) and as NRRD and MetaImage from their specifications. Every format gives the same samples
 * and affine; a rotated or flipped grid puts each sample where the analytic phantom has its value;
 * bad input (truncated, lying headers, gaps, mixed slices, over the memory limit) is one message. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hovox/scan.h"
#include "support/support.h"

static const char *const k_files[] = {"phantom.nii",      "phantom.nii.gz", "phantom2.nii", "phantom.nrrd",
                                      "phantom_raw.nrrd", "phantom.nhdr",   "phantom.mha",  "phantom.mhd",
                                      "dicom"};

/* The phantom in every format into a fresh directory; returns the directory. */
static const char *make_phantom(const char *affine, const char *size, const char *spacing, const char *formats)
{
    static char dir[600];
    snprintf(dir, sizeof dir, "%s/%s", t_tmpdir(), affine);
    char cmd[1400];
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 tests/io/scan/make_phantom.py %s --affine %s --size %s --spacing %s%s%s",
             dir, affine, size, spacing, formats ? " --formats " : "", formats ? formats : "");
    cr_assert_eq(t_run(cmd, NULL), 0, "%s", cmd);
    return dir;
}

static hv_scan *load(const char *dir, const char *name)
{
    char path[800];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    hv_scan *s = NULL;
    cr_assert_eq(hv_scan_load(path, NULL, &s), HV_OK, "%s: %s", path, hv_last_error());
    return s;
}

/* The analytic phantom (make_phantom.py): shell index at a world point and its distance in
 * normalised radius to the nearest shell boundary. */
static const double k_centre[3] = {2, -3, 5}, k_axes[3] = {36, 44, 50};
static double phantom_value(const double p[3], double *margin)
{
    double r = 0;
    for (int a = 0; a < 3; ++a) {
        double q = (p[a] - k_centre[a]) / k_axes[a];
        r += q * q;
    }
    r = sqrt(r);
    static const double s[3] = {1.0, 0.9, 0.8}, v[3] = {40, 1000, 30};
    double val = -1000;
    *margin = 1e9;
    for (int i = 0; i < 3; ++i) {
        if (r <= s[i]) val = v[i];
        *margin = fmin(*margin, fabs(r - s[i]));
    }
    return val;
}

Test(scan, every_format_gives_the_same_samples_and_affine, .timeout = 120)
{
    const char *dir = make_phantom("ras", "40,48,36", "2,2,3", NULL);
    hv_scan *ref = load(dir, "phantom.nii");
    size_t rd[3];
    double rm[12];
    hv_scan_dims(ref, rd);
    hv_scan_affine(ref, rm);
    cr_assert(rd[0] == 40 && rd[1] == 48 && rd[2] == 36);
    size_t n = rd[0] * rd[1] * rd[2];
    for (size_t f = 1; f < sizeof k_files / sizeof *k_files; ++f) {
        hv_scan *s = load(dir, k_files[f]);
        size_t d[3];
        double m[12];
        hv_scan_dims(s, d);
        hv_scan_affine(s, m);
        cr_assert(d[0] == rd[0] && d[1] == rd[1] && d[2] == rd[2], "%s: dims", k_files[f]);
        for (int i = 0; i < 12; ++i) cr_assert(fabs(m[i] - rm[i]) < 1e-5, "%s: affine[%d] %g vs %g", k_files[f], i, m[i], rm[i]);
        cr_assert_eq(memcmp(hv_scan_data(s), hv_scan_data(ref), n * sizeof(float)), 0, "%s: samples differ", k_files[f]);
        hv_scan_destroy(s);
    }
    const hv_scan_info *in = hv_scan_get_info(ref);
    cr_assert_eq(in->value_min, -1000);
    cr_assert_eq(in->value_max, 1000);
    hv_scan_destroy(ref);
    hv_scan *dcm = load(dir, "dicom");
    in = hv_scan_get_info(dcm);
    cr_assert_str_eq(in->unit, "HU");
    cr_assert_eq(in->files, 36);
    cr_assert_eq(in->intercept, -1024);
    hv_scan_destroy(dcm);
}

/* Every sample well inside a shell holds that shell's value at the world place its affine says. */
static void lands_in_world(const char *affine)
{
    const char *dir = make_phantom(affine, "40,48,36", "2,2,3", "nii.gz,nrrd,mha,dicom");
    static const char *const files[] = {"phantom.nii.gz", "phantom.nrrd", "phantom.mha", "dicom"};
    for (size_t f = 0; f < 4; ++f) {
        hv_scan *s = load(dir, files[f]);
        size_t d[3];
        double m[12];
        hv_scan_dims(s, d);
        hv_scan_affine(s, m);
        const float *v = hv_scan_data(s);
        size_t checked = 0;
        for (size_t k = 0; k < d[2]; ++k)
            for (size_t j = 0; j < d[1]; ++j)
                for (size_t i = 0; i < d[0]; ++i) {
                    double p[3], margin;
                    for (int r = 0; r < 3; ++r)
                        p[r] = m[4 * r] * (double)i + m[4 * r + 1] * (double)j + m[4 * r + 2] * (double)k + m[4 * r + 3];
                    double want = phantom_value(p, &margin);
                    if (margin < 0.08) continue; /* a voxel (3 mm) of a 36 mm semi-axis from a boundary */
                    cr_assert_eq(v[i + d[0] * (j + d[1] * k)], want, "%s %s: sample (%zu,%zu,%zu) at (%g,%g,%g)", affine,
                                 files[f], i, j, k, p[0], p[1], p[2]);
                    ++checked;
                }
        cr_assert(checked > d[0] * d[1] * d[2] / 2, "%s: only %zu samples checked", files[f], checked);
        hv_scan_destroy(s);
    }
}

Test(scan, an_axis_aligned_grid_lands_where_world_coordinates_say, .timeout = 120) { lands_in_world("ras"); }
Test(scan, flipped_axes_land_where_world_coordinates_say, .timeout = 120) { lands_in_world("flip"); }
Test(scan, a_rotated_affine_lands_where_world_coordinates_say, .timeout = 120) { lands_in_world("rotated"); }

Test(scan, memory_parse_matches_the_file_reader, .timeout = 120)
{
    const char *dir = make_phantom("ras", "12,10,8", "2,2,3", "nii.gz,nrrd,mha,dicom");
    static const char *const files[] = {"phantom.nii.gz", "phantom.nrrd", "phantom.mha"};
    hv_scan *ref = load(dir, "phantom.nii.gz");
    for (size_t f = 0; f < 3; ++f) {
        char path[800];
        snprintf(path, sizeof path, "%s/%s", dir, files[f]);
        size_t len;
        char *bytes = t_slurp(path, &len);
        hv_scan *s = NULL;
        cr_assert_eq(hv_scan_parse(bytes, len, files[f], NULL, &s), HV_OK, "%s", hv_last_error());
        cr_assert_eq(memcmp(hv_scan_data(s), hv_scan_data(ref), 12 * 10 * 8 * sizeof(float)), 0);
        hv_scan_destroy(s);
        free(bytes);
    }
    hv_scan_destroy(ref);
}

/* The refusal's status and message (after the directory). */
static void refused(const char *path, const hv_scan_options *o, hv_status want, const char *msg)
{
    hv_scan *s = (hv_scan *)1;
    hv_status st = hv_scan_load(path, o, &s);
    cr_assert_eq(st, want, "%s: %s", path, hv_last_error());
    cr_assert_null(s);
    const char *got = strstr(hv_last_error(), msg);
    cr_assert(got != NULL, "message '%s' lacks '%s'", hv_last_error(), msg);
}

Test(scan, bad_input_is_one_message, .timeout = 120)
{
    const char *dir = make_phantom("ras", "12,10,8", "2,2,3", "nii,nrrd.raw,mha,dicom");
    char cmd[2000], p[800];
    /* truncated: the last bytes of the samples cut off */
    snprintf(cmd, sizeof cmd, "cd %s && head -c 1000 phantom.nii > cut.nii && head -c 900 phantom_raw.nrrd > cut.nrrd", dir);
    cr_assert_eq(t_run(cmd, NULL), 0);
    snprintf(p, sizeof p, "%s/cut.nii", dir);
    refused(p, NULL, HV_ERR_BAD_INPUT, "the header says 12 x 10 x 8 int16 samples (1920 bytes) from byte 352; the file holds 648");
    snprintf(p, sizeof p, "%s/cut.nrrd", dir);
    refused(p, NULL, HV_ERR_BAD_INPUT, "the header says 12 x 10 x 8 int16 samples (1920 bytes)");
    /* a header that lies: dim[1] made 1200 */
    snprintf(cmd, sizeof cmd,
             "cd %s && /usr/bin/python3 -c \"import struct;b=bytearray(open('phantom.nii','rb').read());"
             "b[42:44]=struct.pack('<h',1200);open('lies.nii','wb').write(b)\"", dir);
    cr_assert_eq(t_run(cmd, NULL), 0);
    snprintf(p, sizeof p, "%s/lies.nii", dir);
    refused(p, NULL, HV_ERR_BAD_INPUT, "the header says 1200 x 10 x 8 int16 samples (192000 bytes)");
    /* over the memory limit: refused before reading, saying how much */
    hv_scan_options o;
    hv_scan_options_init(&o);
    o.max_memory = 1024;
    snprintf(p, sizeof p, "%s/phantom.mha", dir);
    refused(p, &o, HV_ERR_LIMIT, "the data (12 x 10 x 8 samples) needs 3.8 KiB, more than the limit of 1.0 KiB");
    /* DICOM: a gap, then mixed sizes, then a stranger */
    snprintf(cmd, sizeof cmd, "cd %s && cp -r dicom gap && rm gap/$(/usr/bin/python3 -c \"import pydicom,glob;"
             "f=sorted(glob.glob('gap/*'),key=lambda n:float(pydicom.dcmread(n).ImagePositionPatient[2]))[3];print(f[4:])\")", dir);
    cr_assert_eq(t_run(cmd, NULL), 0, "%s", cmd);
    snprintf(p, sizeof p, "%s/gap", dir);
    refused(p, NULL, HV_ERR_BAD_INPUT, "a gap in the series: 6 mm between");
}

/* hv_scan_transform (a tray part's placement and quarter turns): every sample centre moves by the
 * map, the samples stay; a singular map is refused and leaves the scan as it was. */
Test(scan, a_transform_moves_every_sample_centre, .timeout = 120)
{
    const char *dir = make_phantom("rotated", "12,10,8", "2,2,3", "nii");
    hv_scan *s = load(dir, "phantom.nii");
    double m0[12], m1[12];
    hv_scan_affine(s, m0);
    const double turn[12] = {0, -1, 0, 10, 1, 0, 0, -5, 0, 0, 2, 1}; /* a quarter turn, z doubled, moved */
    cr_assert_eq(hv_scan_transform(s, turn), HV_OK, "%s", hv_last_error());
    hv_scan_affine(s, m1);
    const double idx[4][3] = {{0, 0, 0}, {11, 0, 0}, {0, 9, 7}, {5.5, 4, 3}};
    for (int t = 0; t < 4; ++t) {
        double w0[3], w1[3];
        for (int r = 0; r < 3; ++r) {
            w0[r] = m0[4 * r] * idx[t][0] + m0[4 * r + 1] * idx[t][1] + m0[4 * r + 2] * idx[t][2] + m0[4 * r + 3];
            w1[r] = m1[4 * r] * idx[t][0] + m1[4 * r + 1] * idx[t][1] + m1[4 * r + 2] * idx[t][2] + m1[4 * r + 3];
        }
        for (int r = 0; r < 3; ++r) {
            double want = turn[4 * r] * w0[0] + turn[4 * r + 1] * w0[1] + turn[4 * r + 2] * w0[2] + turn[4 * r + 3];
            cr_assert(fabs(w1[r] - want) < 1e-9, "sample %d axis %d: %g, want %g", t, r, w1[r], want);
        }
    }
    const double flat[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0};
    cr_assert_eq(hv_scan_transform(s, flat), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "singular"), "message: %s", hv_last_error());
    double m2[12];
    hv_scan_affine(s, m2);
    cr_assert_eq(memcmp(m1, m2, sizeof m1), 0, "a refused map changed the scan");
    hv_scan_destroy(s);
}

/* hv_scan_labels_parse: the one parser of "A,B,..." (the CLI's --labels, a tray job's labels). */
Test(scan, labels_text_is_parsed_once)
{
    int32_t *l = NULL;
    size_t n = 0;
    cr_assert_eq(hv_scan_labels_parse("3,-1,2147483647", &l, &n), HV_OK);
    cr_assert_eq(n, 3);
    cr_assert(l[0] == 3 && l[1] == -1 && l[2] == INT32_MAX);
    free(l);
    static const char *const bad[] = {"", "1,x", "1,,2", "2147483648", "1.5", "1,"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; ++i) {
        cr_assert_eq(hv_scan_labels_parse(bad[i], &l, &n), HV_ERR_INVALID, "'%s'", bad[i]);
        cr_assert(l == NULL && n == 0, "'%s'", bad[i]);
        cr_assert(strstr(hv_last_error(), "labels must"), "'%s': %s", bad[i], hv_last_error());
    }
}
