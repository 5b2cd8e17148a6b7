/* tests/voxel/test_scan_voxelize.c - models from scans (issue 30): the head phantom of
 * tests/io/scan/make_phantom.py (nibabel, pydicom, NRRD and MetaImage writers) voxelized at its
 * skin's iso value holds the analytic ellipsoid's volume within 1%; the same phantom in four
 * formats gives identical models; a rotated or flipped grid lands where its world coordinates
 * say; the model's FIELD_ISO leaf cuts the analytic ellipse at a height (marching squares). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/geometry.h"
#include "hovox/scan.h"
#include "hovox/solid.h"
#include "support/support.h"

static const double k_centre[3] = {2, -3, 5}, k_axes[3] = {36, 44, 50};
#define HEAD_VOLUME (4.0 / 3.0 * M_PI * 36 * 44 * 50)

static const char *phantom(const char *affine, const char *formats)
{
    static char dir[600];
    snprintf(dir, sizeof dir, "%s/%s", t_tmpdir(), affine);
    char cmd[1400];
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 tests/io/scan/make_phantom.py %s --affine %s --formats %s", dir, affine,
             formats);
    cr_assert_eq(t_run(cmd, NULL), 0, "%s", cmd);
    return dir;
}

static hv_volume *model(const char *dir, const char *file, double iso, int fill, hv_scan_voxelize_report *r)
{
    char path[800];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    hv_scan *s = NULL;
    cr_assert_eq(hv_scan_load(path, NULL, &s), HV_OK, "%s", hv_last_error());
    hv_scan_voxelize_options o;
    hv_scan_voxelize_options_init(&o);
    o.shape.iso = iso;
    o.fill_holes = fill;
    hv_volume *v = NULL;
    cr_assert_eq(hv_scan_voxelize(s, &o, &v, r), HV_OK, "%s", hv_last_error());
    hv_scan_destroy(s);
    return v;
}

/* Occupancy centroid (world). */
static void centroid(const hv_volume *v, double c[3])
{
    double *xyz = NULL;
    size_t n = 0;
    cr_assert_eq(hv_volume_centres(v, "occupancy", &xyz, &n), HV_OK);
    c[0] = c[1] = c[2] = 0;
    for (size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) c[a] += xyz[3 * i + a] / (double)n;
    free(xyz);
}

/* The skin's iso value: halfway between air (-1000) and skin (40). */
#define SKIN (-480.0)

Test(scan_voxelize, the_iso_volume_is_within_one_percent_of_the_analytic_volume, .timeout = 180)
{
    const char *dir = phantom("ras", "nii.gz");
    hv_scan_voxelize_report r;
    hv_volume *v = model(dir, "phantom.nii.gz", SKIN, 0, &r);
    double err = fabs(r.volume - HEAD_VOLUME) / HEAD_VOLUME;
    cr_log_info("head: voxel volume %.1f, analytic %.1f, error %.3f%%", r.volume, HEAD_VOLUME, 100 * err);
    cr_assert(err < 0.01, "volume %g vs %g (%.2f%%)", r.volume, HEAD_VOLUME, 100 * err);
    double c[3];
    centroid(v, c);
    for (int a = 0; a < 3; ++a) cr_assert(fabs(c[a] - k_centre[a]) < 0.1, "centroid %g vs %g", c[a], k_centre[a]);
    hv_volume_destroy(v);
    /* the skull and the brain inside it, cavity filled: the ellipsoid scaled by 0.9 */
    v = model(dir, "phantom.nii.gz", 520, 1, &r);
    double want = HEAD_VOLUME * 0.729;
    err = fabs(r.volume - want) / want;
    cr_log_info("skull filled: %.1f vs %.1f, error %.3f%%", r.volume, want, 100 * err);
    cr_assert(err < 0.01, "filled skull %g vs %g (%.2f%%)", r.volume, want, 100 * err);
    cr_assert_eq(r.filled_cavities, 1);
    hv_volume_destroy(v);
}

Test(scan_voxelize, four_formats_give_identical_models, .timeout = 180)
{
    const char *dir = phantom("ras", "nii,nrrd,mha,dicom");
    static const char *const files[] = {"phantom.nii", "phantom.nrrd", "phantom.mha", "dicom"};
    hv_volume *ref = model(dir, files[0], SKIN, 0, NULL);
    int32_t lo[3], hi[3];
    cr_assert(hv_volume_index_bbox(ref, lo, hi));
    size_t n = (size_t)(hi[0] - lo[0] + 1) * (size_t)(hi[1] - lo[1] + 1) * (size_t)(hi[2] - lo[2] + 1);
    uint8_t *a = malloc(n), *b = malloc(n);
    cr_assert_eq(hv_volume_dense_mask(ref, hv_volume_grid_find(ref, "occupancy"), lo, hi, a), HV_OK);
    for (int f = 1; f < 4; ++f) {
        hv_volume *v = model(dir, files[f], SKIN, 0, NULL);
        int32_t l2[3], h2[3];
        cr_assert(hv_volume_index_bbox(v, l2, h2));
        cr_assert(!memcmp(l2, lo, sizeof lo) && !memcmp(h2, hi, sizeof hi), "%s: another box", files[f]);
        cr_assert_eq(hv_volume_dense_mask(v, hv_volume_grid_find(v, "occupancy"), lo, hi, b), HV_OK);
        cr_assert_eq(memcmp(a, b, n), 0, "%s: another occupancy", files[f]);
        hv_volume_destroy(v);
    }
    free(a);
    free(b);
    hv_volume_destroy(ref);
}

static void lands(const char *affine)
{
    const char *dir = phantom(affine, "nii.gz,dicom");
    static const char *const files[] = {"phantom.nii.gz", "dicom"};
    for (int f = 0; f < 2; ++f) {
        hv_scan_voxelize_report r;
        hv_volume *v = model(dir, files[f], SKIN, 0, &r);
        double c[3], err = fabs(r.volume - HEAD_VOLUME) / HEAD_VOLUME;
        centroid(v, c);
        cr_assert(err < 0.01, "%s %s: volume %g (%.2f%%)", affine, files[f], r.volume, 100 * err);
        for (int a = 0; a < 3; ++a)
            cr_assert(fabs(c[a] - k_centre[a]) < 0.15, "%s %s: centroid[%d] %g vs %g", affine, files[f], a, c[a], k_centre[a]);
        hv_volume_destroy(v);
    }
}

Test(scan_voxelize, a_rotated_grid_lands_where_its_world_coordinates_say, .timeout = 180) { lands("rotated"); }
Test(scan_voxelize, flipped_axes_land_where_their_world_coordinates_say, .timeout = 180) { lands("flip"); }

static double loop_area(const hv_slice_loop *L)
{
    double a = 0;
    for (size_t i = 0, j = L->count - 1; i < L->count; j = i++)
        a += L->xy[2 * j] * L->xy[2 * i + 1] - L->xy[2 * i] * L->xy[2 * j + 1];
    return a / 2;
}

Test(scan_voxelize, the_field_leaf_cuts_the_analytic_ellipse, .timeout = 180)
{
    const char *dir = phantom("rotated", "nii.gz");
    hv_volume *v = model(dir, "phantom.nii.gz", SKIN, 0, NULL);
    hv_geometry *g = NULL;
    cr_assert_eq(hv_geometry_read(v, &g), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_geometry_leaf_count(g), 1);
    cr_assert_eq(hv_geometry_leaf_at(g, 0)->kind, HV_LEAF_FIELD_ISO);
    hv_solid *s = NULL;
    cr_assert_eq(hv_solid_open(g, NULL, &s), HV_OK, "%s", hv_last_error());
    const hv_leaf *leaf = hv_solid_leaf(s, 0);
    double lo[3], hi[3];
    hv_leaf_bbox(leaf, lo, hi);
    /* the box holds the ellipsoid (a rotated grid's box of the inside samples is looser) */
    for (int a = 0; a < 3; ++a) {
        cr_assert(lo[a] < k_centre[a] - k_axes[a] + 0.3 && lo[a] > k_centre[a] - 2 * k_axes[a], "bbox min[%d] %g", a, lo[a]);
        cr_assert(hi[a] > k_centre[a] + k_axes[a] - 0.3 && hi[a] < k_centre[a] + 2 * k_axes[a], "bbox max[%d] %g", a, hi[a]);
    }
    /* at z = centre + 20: the ellipse of semi-axes a, b scaled by sqrt(1 - (20/50)^2) */
    double z = k_centre[2] + 20, s2 = 1 - 0.16;
    hv_slice *sl = NULL;
    cr_assert_eq(hv_leaf_slice(leaf, z, NULL, &sl), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_slice_loop_count(sl), 1);
    const hv_slice_loop *L = hv_slice_loops(sl);
    double area = loop_area(&L[0]), want = M_PI * 36 * 44 * s2;
    cr_log_info("leaf section: %.2f vs %.2f mm^2 (%.3f%%), %zu points", area, want, 100 * (area - want) / want, L[0].count);
    cr_assert(fabs(area - want) / want < 0.005, "section area %g vs %g", area, want);
    cr_assert_eq(L[0].orientation, 1);
    hv_slice_destroy(sl);
    double in[3] = {k_centre[0], k_centre[1], k_centre[2]}, out[3] = {k_centre[0] + 40, k_centre[1], k_centre[2]};
    cr_assert(hv_leaf_inside(leaf, in));
    cr_assert(!hv_leaf_inside(leaf, out));
    hv_solid_close(s);
    hv_geometry_destroy(g);
    hv_volume_destroy(v);
}
