/* tests/slicing/test_scan_source.c - a scan printed straight from its data (slicing/scan_source.c,
 * issue 30 item 4): at every pixel centre of a layer the source's mask is the level function's
 * test (src/io/scan/level.c, trilinear) and its fractions are the lookup table's at the
 * interpolated value, on an axis-aligned grid (the row-blend path), a rotated one (the stepped
 * index path), for a range and for labels; the source's box is the inside's. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/layers.h"
#include "hovox/lut.h"
#include "hovox/scan.h"
#include "io/scan/scan_internal.h"
#include "slicing/layers_internal.h"
#include "slicing/scan_source.h"
#include "support/support.h"

static hv_scan *phantom(const char *affine)
{
    char dir[600], cmd[1400], path[700];
    snprintf(dir, sizeof dir, "%s/%s", t_tmpdir(), affine);
    snprintf(cmd, sizeof cmd,
             "/usr/bin/python3 tests/io/scan/make_phantom.py %s --size 40,48,36 --spacing 2,2,3 --affine %s "
             "--formats nii >/dev/null",
             dir, affine);
    cr_assert_eq(t_run(cmd, NULL), 0, "%s", cmd);
    snprintf(path, sizeof path, "%s/phantom.nii", dir);
    hv_scan *s = NULL;
    cr_assert_eq(hv_scan_load(path, NULL, &s), HV_OK, "%s", hv_last_error());
    return s;
}

static const char k_table[] = "HU,A,B,C\n-1000,1,0,0\n0,0,1,0\n300,0,1,0\n1000,0,0,1\n";

/* Every pixel of a few layers against the level function and the table; returns the object
 * pixels seen. */
static size_t check(hv_scan *scan, const hv_scan_shape *shape)
{
    hv_lut *lut = NULL;
    cr_assert_eq(hv_lut_parse(k_table, strlen(k_table), "t.csv", &lut), HV_OK, "%s", hv_last_error());
    hv_scan_source *src = NULL;
    cr_assert_eq(hv_scan_source_open(scan, shape, lut, NULL, &src), HV_OK, "%s", hv_last_error());
    const hv_layers_source *ls = hv_scan_source_layers(src);
    cr_assert_eq(hv_material_count(hv_layers_source_table(ls)), 3);
    hv_scan_level lv, val;
    cr_assert_eq(hv_scan_level_init(scan, shape, &lv), HV_OK);
    hv_scan_shape plain = {.select = HV_SCAN_SELECT_ISO, .iso = 0};
    cr_assert_eq(hv_scan_level_init(scan, &plain, &val), HV_OK);
    /* the box is the inside's */
    double lo[3], hi[3];
    cr_assert_eq(hv_scan_inside_box(&lv, lo, hi), HV_OK);
    for (int a = 0; a < 3; ++a) {
        cr_assert_eq(ls->bbox_min[a], lo[a]);
        cr_assert_eq(ls->bbox_max[a], hi[a]);
        cr_assert(lo[a] < hi[a]);
    }
    hv_raster_grid grid = {.width = 120, .height = 110, .pixel = {0.9, -0.95}};
    grid.origin[0] = lo[0] - 3;
    grid.origin[1] = hi[1] + 3;
    size_t plane = (size_t)grid.width * (size_t)grid.height, object = 0;
    uint8_t *mask = malloc(plane);
    float *frac = calloc(3 * plane, sizeof *frac);
    for (int l = 1; l < 8; ++l) {
        double z = lo[2] + (hi[2] - lo[2]) * l / 8.0;
        cr_assert_eq(ls->layer(ls, z, &grid, mask, frac, plane), HV_OK, "%s", hv_last_error());
        for (int r = 0; r < grid.height; ++r)
            for (int c = 0; c < grid.width; ++c) {
                size_t p = (size_t)r * (size_t)grid.width + (size_t)c;
                double pt[3] = {grid.origin[0] + (c + 0.5) * grid.pixel[0], grid.origin[1] + (r + 0.5) * grid.pixel[1], z};
                double g = hv_scan_level_at(&lv, pt);
                if (fabs(g) > 1e-6) cr_assert_eq(mask[p], g >= 0, "layer %d pixel %d,%d: g %g", l, c, r, g);
                if (!mask[p]) continue;
                ++object;
                float want[3];
                hv_lut_eval(lut, hv_scan_level_at(&val, pt), want);
                for (int k = 0; k < 3; ++k)
                    cr_assert(fabsf(frac[(size_t)k * plane + p] - want[k]) < 2e-3f, "pixel %d,%d material %d: %g, not %g",
                              c, r, k, (double)frac[(size_t)k * plane + p], (double)want[k]);
            }
    }
    free(mask);
    free(frac);
    hv_scan_level_free(&lv);
    hv_scan_level_free(&val);
    hv_scan_source_close(src);
    hv_lut_destroy(lut);
    return object;
}

Test(scan_source, axis_aligned_grid_is_the_level_function_and_the_table)
{
    hv_scan *s = phantom("ras");
    hv_scan_shape sh = {.select = HV_SCAN_SELECT_ISO, .iso = -480};
    cr_assert_gt(check(s, &sh), 10000);
    hv_scan_destroy(s);
}

Test(scan_source, rotated_grid_is_the_level_function_and_the_table)
{
    hv_scan *s = phantom("rotated");
    hv_scan_shape sh = {.select = HV_SCAN_SELECT_ISO, .iso = -480};
    cr_assert_gt(check(s, &sh), 10000);
    hv_scan_destroy(s);
}

Test(scan_source, range_and_labels)
{
    hv_scan *s = phantom("ras");
    hv_scan_shape sh = {.select = HV_SCAN_SELECT_RANGE, .range = {-480, 500}};
    cr_assert_gt(check(s, &sh), 10000);
    /* the phantom's values as labels: the brain's 30 HU */
    int32_t labels[1] = {30};
    hv_scan_shape lb = {.select = HV_SCAN_SELECT_LABELS, .labels = labels, .label_count = 1};
    cr_assert_gt(check(s, &lb), 1000);
    hv_scan_destroy(s);
}
