/* tests/colour/test_lut.c - lookup tables from data values to materials (hv_lut_*, src/colour/lut.c):
 * a table evaluates to the straight line between its rows (worked out here by hand, not by the
 * code under test) and to its end rows beyond them; every malformed table is refused with one
 * message naming the file, the line and the value; a scan's model painted from a table holds at
 * each voxel the table at the scan's value there: a ramp volume (value 100 x) whose voxel centres
 * sit between samples, so the trilinear value and the interpolation between rows both count. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/lut.h"
#include "hovox/material.h"
#include "support/support.h"

static hv_lut *parse(const char *text)
{
    hv_lut *t = NULL;
    cr_assert_eq(hv_lut_parse(text, strlen(text), "t.csv", &t), HV_OK, "%s", hv_last_error());
    return t;
}

Test(lut, materials_interpolate_linearly_and_hold_their_end_rows)
{
    hv_lut *t = parse("# bone\r\nHU, VeroClear ,Agilus30,VeroWhite\r\n\n-1000,1,0,0\n0,0,1,0\n300,0,1,0\n1000,0,0.25,0.75\n");
    cr_assert_eq(hv_lut_kind_of(t), HV_LUT_MATERIALS);
    cr_assert_str_eq(hv_lut_value_name(t), "HU");
    cr_assert_eq(hv_lut_columns(t), 3);
    cr_assert_str_eq(hv_lut_material(t, 0), "VeroClear");
    cr_assert_str_eq(hv_lut_material(t, 2), "VeroWhite");
    cr_assert_null(hv_lut_material(t, 3));
    cr_assert_eq(hv_lut_rows(t), 4);
    /* value, expected fractions (by hand) */
    static const double k[][4] = {{-5000, 1, 0, 0},       {-1000, 1, 0, 0},     {-750, 0.75, 0.25, 0},
                                  {-1, 0.001, 0.999, 0},  {150, 0, 1, 0},       {650, 0, 0.625, 0.375},
                                  {1000, 0, 0.25, 0.75},  {1e9, 0, 0.25, 0.75}};
    for (size_t i = 0; i < sizeof k / sizeof *k; ++i) {
        float f[3];
        hv_lut_eval(t, k[i][0], f);
        for (int c = 0; c < 3; ++c)
            cr_expect(fabs(f[c] - k[i][1 + c]) < 1e-6, "value %g column %d: %g, expected %g", k[i][0], c, f[c],
                      k[i][1 + c]);
    }
    double lo, hi;
    hv_lut_range(t, &lo, &hi);
    cr_expect(lo == -1000 && hi == 1000);
    hv_lut_destroy(t);
}

Test(lut, colours_interpolate_per_channel_with_alpha)
{
    hv_lut *t = parse("value,colour\n0,#000000\n100,#ff8000cc\n");
    cr_assert_eq(hv_lut_kind_of(t), HV_LUT_COLOUR);
    cr_assert_eq(hv_lut_columns(t), 4);
    float c[4];
    hv_lut_eval(t, 25, c);
    cr_expect(fabs(c[0] - 0.25) < 1e-6 && fabs(c[1] - 0.25 * 128 / 255.0) < 1e-6 && fabs(c[2]) < 1e-6 &&
                  fabs(c[3] - (0.75 + 0.25 * 204 / 255.0)) < 1e-6,
              "%g %g %g %g", c[0], c[1], c[2], c[3]);
    hv_lut_destroy(t);
    t = parse("HU,color\n-1,#FFFFFF\n");
    hv_lut_eval(t, 5, c);
    cr_expect(c[0] == 1 && c[1] == 1 && c[2] == 1 && c[3] == 1);
    hv_lut_destroy(t);
}

Test(lut, bad_tables_are_one_message_with_file_and_line)
{
    static const char *const k[][2] = {
        {"", "t.csv: empty: no header line '<value name>,<materials...>' or '<value name>,colour'"},
        {"# only a comment\n", "t.csv: empty: no header line '<value name>,<materials...>' or '<value name>,colour'"},
        {"HU,A,B\n", "t.csv: line 1: a header and no rows"},
        {"HU\n0\n", "t.csv: line 1: header 'HU' needs a value name and at least one material or 'colour'"},
        {"H U,A\n0,1\n", "t.csv: line 1: value name 'H U' is not 1-32 characters of [A-Za-z0-9_-]"},
        {"HU,A,a b\n0,1,0\n", "t.csv: line 1: material 'a b' is not 1-64 characters of [A-Za-z0-9_-]"},
        {"HU,A,A\n0,1,0\n", "t.csv: line 1: material 'A' twice"},
        {"HU,A,B\n0,1,0\n1,1\n", "t.csv: line 3: expected 3 fields (HU and 2 materials), got 2"},
        {"HU,A,B\n0,1,0\n\n# c\n0,0,1\n", "t.csv: line 5: HU 0 is not greater than line 2's (0)"},
        {"HU,A,B\n5,1,0\n-3,0,1\n", "t.csv: line 3: HU -3 is not greater than line 2's (5)"},
        {"HU,A,B\nnan,1,0\n", "t.csv: line 2: HU 'nan' is not a finite number"},
        {"HU,A,B\n1e999,1,0\n", "t.csv: line 2: HU '1e999' is not a finite number"},
        {"HU,A,B\n0,0.5,0.4\n", "t.csv: line 2: fractions sum to 0.9, not 1"},
        {"HU,A,B\n0,1.5,-0.5\n", "t.csv: line 2: A fraction '1.5' is not a number in [0, 1]"},
        {"HU,A,B\n0,x,1\n", "t.csv: line 2: A fraction 'x' is not a number in [0, 1]"},
        {"HU,colour\n0,#12\n", "t.csv: line 2: colour '#12' is not #rrggbb or #rrggbbaa"},
        {"HU,colour\n0,#12345g\n", "t.csv: line 2: colour '#12345g' is not #rrggbb or #rrggbbaa"},
        {"HU,colour\n0,1,0,0\n", "t.csv: line 2: expected 2 fields (HU and a colour), got 4"},
        {"HU,A\n0,1\n\x00", "t.csv: line 3: NUL byte in text"},
    };
    for (size_t i = 0; i < sizeof k / sizeof *k; ++i) {
        hv_lut *t = (hv_lut *)1;
        size_t len = strlen(k[i][0]) + (strstr(k[i][1], "NUL") ? 1 : 0);
        cr_expect_eq(hv_lut_parse(k[i][0], len, "t.csv", &t), HV_ERR_BAD_INPUT, "case %zu", i);
        cr_expect_null(t, "case %zu hands out a table", i);
        cr_expect_str_eq(hv_last_error(), k[i][1], "case %zu", i);
    }
    /* more than the row limit */
    size_t cap = 20 * (HV_LUT_MAX_ROWS + 2);
    char *big = malloc(cap);
    size_t n = (size_t)snprintf(big, cap, "HU,A\n");
    for (int r = 0; r <= HV_LUT_MAX_ROWS; ++r) n += (size_t)snprintf(big + n, cap - n, "%d,1\n", r);
    hv_lut *t = NULL;
    cr_expect_eq(hv_lut_parse(big, n, "t.csv", &t), HV_ERR_BAD_INPUT);
    cr_expect_str_eq(hv_last_error(), "t.csv: line 4098: more than 4096 rows");
    free(big);
    cr_expect_eq(hv_lut_load("/nonexistent/t.csv", &t), HV_ERR_IO);
}

/* A ramp: 8 x 4 x 4 float samples, value 100 i, sample (i, j, k) at world (i, j, k) mm. */
static hv_scan *ramp(void)
{
    const char *head = "NRRD0004\ntype: float\ndimension: 3\nsizes: 8 4 4\nspace: right-anterior-superior\n"
                       "space directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: (0,0,0)\nendian: little\n"
                       "encoding: raw\n\n";
    size_t hn = strlen(head), n = 8 * 4 * 4;
    unsigned char *buf = malloc(hn + 4 * n);
    memcpy(buf, head, hn);
    for (size_t p = 0; p < n; ++p) {
        float v = (float)(100 * (p % 8));
        memcpy(buf + hn + 4 * p, &v, 4); /* the machine is little-endian (x86-64, as the build) */
    }
    hv_scan *s = NULL;
    cr_assert_eq(hv_scan_parse(buf, hn + 4 * n, "ramp.nrrd", NULL, &s), HV_OK, "%s", hv_last_error());
    free(buf);
    return s;
}

Test(lut, a_scans_model_holds_the_table_at_each_voxels_value)
{
    hv_scan *scan = ramp();
    hv_scan_voxelize_options o;
    hv_scan_voxelize_options_init(&o);
    o.shape.iso = -1; /* every cell */
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.5;
    hv_volume *vol = NULL;
    cr_assert_eq(hv_scan_voxelize(scan, &o, &vol, NULL), HV_OK, "%s", hv_last_error());
    hv_lut *t = parse("v,Soft,Hard\n100,1,0\n500,0,1\n");
    cr_assert_eq(hv_lut_paint_scan(vol, scan, t, NULL, 0, NULL), HV_OK, "%s", hv_last_error());
    int g[2] = {hv_volume_grid_find(vol, "material.Soft"), hv_volume_grid_find(vol, "material.Hard")};
    cr_assert(g[0] >= 0 && g[1] >= 0);
    hv_material_table *mt = NULL;
    cr_assert_eq(hv_material_table_load(vol, &mt), HV_OK, "%s", hv_last_error());
    cr_expect_eq(hv_material_count(mt), 2);
    cr_expect_str_eq(hv_material_name(mt, 1), "Hard");
    hv_material_table_destroy(mt);
    double *xyz = NULL;
    size_t n = 0;
    cr_assert_eq(hv_volume_centres(vol, "occupancy", &xyz, &n), HV_OK);
    cr_expect_eq(n, 16 * 8 * 8, "the cells' box [-0.5, 7.5] x [-0.5, 3.5]^2 in 0.5 mm voxels: %zu", n);
    hv_accessor acc;
    hv_accessor_init(&acc, vol);
    for (size_t i = 0; i < n; ++i) {
        const double *p = xyz + 3 * i;
        double idx[3];
        hv_volume_world_to_index(vol, p, idx);
        int32_t v[3] = {(int32_t)lrint(idx[0]), (int32_t)lrint(idx[1]), (int32_t)lrint(idx[2])};
        double value = 100 * fmin(fmax(p[0], 0), 7);           /* the ramp, edge samples held */
        double hard = fmin(fmax((value - 100) / 400, 0), 1);   /* the table by hand */
        float got[2] = {hv_accessor_float(&acc, g[0], v[0], v[1], v[2]), hv_accessor_float(&acc, g[1], v[0], v[1], v[2])};
        cr_expect(fabs(got[1] - hard) < 1e-5 && fabs(got[0] - (1 - hard)) < 1e-5, "at x = %g: %g %g, expected %g",
                  p[0], got[0], got[1], hard);
    }
    free(xyz);
    /* a second table on the same model: its materials are there already */
    cr_expect_neq(hv_lut_paint_scan(vol, scan, t, NULL, 0, NULL), HV_OK);
    hv_lut_destroy(t);
    /* a colour table needs a colour map; and the memory plan refuses a tiny budget */
    t = parse("v,colour\n0,#ff0000\n");
    cr_expect_eq(hv_lut_paint_scan(vol, scan, t, NULL, 0, NULL), HV_ERR_INVALID);
    hv_lut_destroy(t);
    t = parse("v,A\n0,1\n");
    cr_expect_eq(hv_lut_paint_scan(vol, scan, t, NULL, 1000, NULL), HV_ERR_LIMIT);
    cr_expect(strstr(hv_last_error(), "more than the limit of") != NULL, "%s", hv_last_error());
    hv_lut_destroy(t);
    hv_volume_destroy(vol);
    hv_scan_destroy(scan);
}

Test(lut, a_colour_table_gives_the_colour_maps_fractions_of_the_interpolated_colour)
{
    hv_scan *scan = ramp();
    hv_scan_voxelize_options o;
    hv_scan_voxelize_options_init(&o);
    o.shape.iso = -1;
    hv_volume *vol = NULL;
    cr_assert_eq(hv_scan_voxelize(scan, &o, &vol, NULL), HV_OK, "%s", hv_last_error());
    hv_colour_options co;
    hv_colour_options_init(&co);
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_create(&co, &map), HV_OK, "%s", hv_last_error());
    hv_lut *t = parse("v,colour\n0,#000000\n700,#ffffff\n");
    cr_assert_eq(hv_lut_paint_scan(vol, scan, t, map, 0, NULL), HV_OK, "%s", hv_last_error());
    int g[HV_COLOUR_SLOTS];
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
        char name[160];
        snprintf(name, sizeof name, "material.%s", hv_colour_map_resin(map, k));
        cr_assert((g[k] = hv_volume_grid_find(vol, name)) >= 0, "%s", name);
    }
    hv_accessor acc;
    hv_accessor_init(&acc, vol);
    /* 1 mm voxels centred at x = n + 1/2: value 100 x, grey 255 x / 7 */
    for (int i = 0; i < 7; ++i) {
        double x = i + 0.5;
        uint8_t grey = (uint8_t)lrint(255 * x / 7), rgba[4] = {grey, grey, grey, 255};
        float want[HV_COLOUR_SLOTS];
        hv_colour_map_fractions(map, rgba, want);
        double sum = 0;
        for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
            float got = hv_accessor_float(&acc, g[k], i, 1, 1);
            sum += got;
            cr_expect(fabs(got - want[k]) < 1e-6, "x %g slot %d: %g, expected %g", x, k, got, want[k]);
        }
        cr_expect(fabs(sum - 1) < 1e-5, "x %g: fractions sum to %g", x, sum);
    }
    hv_lut_destroy(t);
    hv_colour_map_destroy(map);
    hv_volume_destroy(vol);
    hv_scan_destroy(scan);
}
