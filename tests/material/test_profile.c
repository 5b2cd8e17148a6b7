/* tests/material/test_profile.c - material profiles along a line (Wu Fig. 26): sample
 * positions and distances, inside flags and fractions against closed-form references
 * (fractions linear in the voxel index, so trilinear samples inside equal the formula; the
 * occupancy of a box known per axis), CSV output read back, thread-count independence, the
 * profile plot checked pixel by pixel, and the errors. */
#include <cairo.h>
#include <criterion/criterion.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/plot.h"
#include "hovox/profile.h"
#include "support/support.h"

/* ---- graded volumes built directly --------------------------------------------------------- */

/* Activate the voxels [lo, hi] (inclusive) of a box. */
static void add_box(hv_volume *v, const int lo[3], const int hi[3])
{
    cr_assert_eq(t_add_box(v, lo, hi), HV_OK, "%s", hv_last_error());
}

typedef void (*frac_fn)(int i, int j, int k, double *f);

/* Occupancy on every active voxel, material grids from fn, the table stored (if names). */
static void grade(hv_volume *v, const char *const *names, int m, frac_fn fn, int store)
{
    hv_material_table *t;
    cr_assert_eq(hv_material_table_create(&t), HV_OK);
    int occ, g[8];
    cr_assert_eq(hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &occ), HV_OK);
    for (int k = 0; k < m; ++k) {
        char name[80];
        snprintf(name, sizeof name, "material.%s", names[k]);
        cr_assert_eq(hv_volume_grid_add(v, name, HV_GRID_FLOAT, &g[k]), HV_OK);
        cr_assert_eq(hv_material_add(t, names[k], NULL, NULL), HV_OK);
    }
    const int32_t *org = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        const uint64_t *mask = hv_volume_leaf_mask(v, l);
        uint64_t *ob = hv_volume_leaf_bool(v, occ, l);
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
            if (!HV_BIT_GET(mask, n)) continue;
            ob[n / 64] |= 1ull << (n % 64);
            double f[8];
            fn(org[3 * l] + (int)(n >> 6), org[3 * l + 1] + (int)((n >> 3) & 7), org[3 * l + 2] + (int)(n & 7), f);
            for (int k = 0; k < m; ++k) hv_volume_leaf_float(v, g[k], l)[n] = (float)f[k];
        }
    }
    if (store) cr_assert_eq(hv_material_table_store(v, t), HV_OK);
    hv_material_table_destroy(t);
}

/* rigid = i/15, soft = 1 - i/15 on 16^3 voxels of 0.5 mm, voxel 0 at (1, 2, 3):
 * in world terms rigid(x) = (x - 1) / 7.5 for x in [1, 8.5]. */
static void linear_fn(int i, int j, int k, double *f)
{
    (void)j, (void)k;
    f[1] = i / 15.0;
    f[0] = 1.0 - f[1];
}

static const char *const LINEAR_NAMES[2] = {"soft", "rigid"};

static hv_volume *linear_model(void)
{
    hv_transform xf = {{0.5, 0.5, 0.5}, {1.0, 2.0, 3.0}};
    hv_volume *v;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK, "%s", hv_last_error());
    add_box(v, (int[3]){0, 0, 0}, (int[3]){15, 15, 15});
    grade(v, LINEAR_NAMES, 2, linear_fn, 1);
    return v;
}

static double rigid_at(double x) { return (x - 1.0) / 7.5; }

/* ---- sampling ---------------------------------------------------------------------------- */

Test(profile, samples_are_evenly_spaced_and_hit_both_ends)
{
    hv_volume *v = linear_model();
    /* -3 + (-0.9 - -3) != -0.9 in doubles: the ends must still come out exactly */
    double a[3] = {-3.0, 2.3, 3.4}, b[3] = {-0.9, 9.1, 10.2};
    hv_profile *p;
    cr_assert_eq(hv_profile_sample(v, a, b, 57, &p), HV_OK, "%s", hv_last_error());
    double len = sqrt(2.1 * 2.1 + 6.8 * 6.8 + 6.8 * 6.8);
    cr_expect_eq(hv_profile_samples(p), 57);
    cr_expect_eq(hv_profile_materials(p), 2);
    cr_expect(fabs(hv_profile_length(p) - len) < 1e-12);
    for (int i = 0; i < 57; ++i) {
        double x[3];
        hv_profile_position(p, i, x);
        cr_expect(fabs(hv_profile_t(p, i) - len * i / 56.0) < 1e-12, "t[%d] = %.17g", i, hv_profile_t(p, i));
        for (int k = 0; k < 3; ++k)
            cr_expect(fabs(x[k] - (a[k] + (b[k] - a[k]) * i / 56.0)) < 1e-12, "sample %d axis %d", i, k);
    }
    double first[3], last[3];
    hv_profile_position(p, 0, first);
    hv_profile_position(p, 56, last);
    cr_expect_eq(memcmp(first, a, sizeof a), 0, "first sample is not exactly --from");
    cr_expect_eq(memcmp(last, b, sizeof b), 0, "last sample is not exactly --to");
    hv_profile_destroy(p);
    hv_volume_destroy(v);
}

Test(profile, linear_fractions_match_the_formula_inside)
{
    hv_volume *v = linear_model();
    /* a skew line well inside the box: trilinear interpolation of a linear field is exact */
    double a[3] = {1.2, 2.3, 3.4}, b[3] = {8.3, 9.1, 10.2};
    hv_profile *p;
    cr_assert_eq(hv_profile_sample(v, a, b, 301, &p), HV_OK, "%s", hv_last_error());
    const hv_material_table *t = hv_profile_table(p);
    cr_expect_str_eq(hv_material_name(t, 0), "soft");
    cr_expect_str_eq(hv_material_name(t, 1), "rigid");
    for (int i = 0; i < 301; ++i) {
        double x[3];
        hv_profile_position(p, i, x);
        const double *f = hv_profile_fractions(p, i);
        cr_expect_eq(hv_profile_inside(p, i), 1, "sample %d outside", i);
        cr_expect(fabs(f[1] - rigid_at(x[0])) < 2e-6, "sample %d: rigid %.9g, formula %.9g", i, f[1], rigid_at(x[0]));
        cr_expect(fabs(f[0] - (1 - rigid_at(x[0]))) < 2e-6, "sample %d: soft %.9g", i, f[0]);
    }
    hv_profile_destroy(p);
    hv_volume_destroy(v);
}

/* Coverage of the box along x for a line through voxel centres in y and z: 1 on [0, 15] in
 * index units, falling linearly to 0 one voxel beyond. */
static double coverage_x(double ix)
{
    double d = ix < 0 ? -ix : ix > 15 ? ix - 15 : 0;
    return d >= 1 ? 0 : 1 - d;
}

Test(profile, inside_and_boundary_values_follow_the_occupancy)
{
    hv_volume *v = linear_model();
    double y = 2.0 + 0.5 * 5, z = 3.0 + 0.5 * 7; /* voxel centres */
    double a[3] = {-1.013, y, z}, b[3] = {11.021, y, z};
    int n = 487;
    hv_profile *p;
    cr_assert_eq(hv_profile_sample(v, a, b, n, &p), HV_OK, "%s", hv_last_error());
    int checked = 0;
    for (int i = 0; i < n; ++i) {
        double x[3];
        hv_profile_position(p, i, x);
        double ix = (x[0] - 1.0) / 0.5, cov = coverage_x(ix);
        const double *f = hv_profile_fractions(p, i);
        if (fabs(cov - 0.5) < 1e-9) continue;
        ++checked;
        cr_expect_eq(hv_profile_inside(p, i), cov >= 0.5, "x = %g: inside %d, coverage %g", x[0], hv_profile_inside(p, i), cov);
        /* renormalised fractions: the nearest occupied voxels' values up to one voxel out, 0
         * beyond */
        double want = cov == 0 ? 0 : rigid_at(fmin(fmax(x[0], 1.0), 8.5));
        double want_soft = cov == 0 ? 0 : 1 - want;
        cr_expect(fabs(f[1] - want) < 2e-6, "x = %g: rigid %g, want %g", x[0], f[1], want);
        cr_expect(fabs(f[0] - want_soft) < 2e-6, "x = %g: soft %g, want %g", x[0], f[0], want_soft);
    }
    cr_expect_gt(checked, n - 3);
    hv_profile_destroy(p);
    hv_volume_destroy(v);
}

Test(profile, result_does_not_depend_on_the_thread_count)
{
    hv_volume *v = linear_model();
    double a[3] = {0.3, 1.1, 2.2}, b[3] = {9.4, 10.1, 8.8};
    hv_profile *p1, *p4;
    hv_set_threads(1);
    cr_assert_eq(hv_profile_sample(v, a, b, 20011, &p1), HV_OK);
    hv_set_threads(4);
    cr_assert_eq(hv_profile_sample(v, a, b, 20011, &p4), HV_OK);
    hv_set_threads(0);
    for (int i = 0; i < 20011; ++i) {
        cr_assert_eq(hv_profile_inside(p1, i), hv_profile_inside(p4, i));
        cr_assert_eq(memcmp(hv_profile_fractions(p1, i), hv_profile_fractions(p4, i), 2 * sizeof(double)), 0, "sample %d", i);
        cr_assert_eq(hv_profile_t(p1, i), hv_profile_t(p4, i));
    }
    hv_profile_destroy(p1);
    hv_profile_destroy(p4);
    hv_volume_destroy(v);
}

/* ---- CSV --------------------------------------------------------------------------------- */


Test(profile, csv_rows_hold_the_samples)
{
    hv_volume *v = linear_model();
    double a[3] = {0.0, 5.75, 6.75}, b[3] = {9.5, 5.75, 6.75};
    hv_profile *p;
    cr_assert_eq(hv_profile_sample(v, a, b, 77, &p), HV_OK);
    const char *path = t_tmpfile("p.csv");
    cr_assert_eq(hv_profile_write_csv(p, path), HV_OK, "%s", hv_last_error());
    char *text = t_slurp(path, NULL);
    char *save = NULL, *line = strtok_r(text, "\n", &save);
    cr_assert_str_eq(line, "t,x,y,z,inside,soft,rigid");
    int rows = 0;
    while ((line = strtok_r(NULL, "\n", &save))) {
        double t, x, y, z, soft, rigid;
        int inside, used = 0;
        cr_assert_eq(sscanf(line, "%lf,%lf,%lf,%lf,%d,%lf,%lf%n", &t, &x, &y, &z, &inside, &soft, &rigid, &used), 7, "row %d: %s", rows, line);
        cr_assert_eq(line[used], '\0', "row %d has extra fields: %s", rows, line);
        /* independent reference: the segment and the closed-form fractions */
        cr_expect(fabs(t - 9.5 * rows / 76.0) < 1e-8, "row %d: t = %.9g", rows, t);
        cr_expect(fabs(x - 9.5 * rows / 76.0) < 1e-8 && y == 5.75 && z == 6.75, "row %d: %s", rows, line);
        double ix = (x - 1.0) / 0.5;
        int want_in = coverage_x(ix) >= 0.5;
        cr_expect_eq(inside, want_in, "row %d: %s", rows, line);
        if (ix >= 0 && ix <= 15) cr_expect(fabs(rigid - rigid_at(x)) < 5e-6, "row %d: %s", rows, line);
        /* and exactly what the profile holds, to the printed precision */
        const double *f = hv_profile_fractions(p, rows);
        cr_expect(fabs(rigid - f[1]) <= 5e-6 * fabs(f[1]) + 1e-12 && fabs(soft - f[0]) <= 5e-6 * fabs(f[0]) + 1e-12, "row %d", rows);
        ++rows;
    }
    cr_expect_eq(rows, 77);
    free(text);

    /* the stream form writes the same bytes */
    const char *spath = t_tmpfile("s.csv");
    FILE *f = fopen(spath, "w");
    cr_assert_eq(hv_profile_write_csv_stream(p, f), HV_OK);
    fclose(f);
    char *x1 = t_slurp(path, NULL), *x2 = t_slurp(spath, NULL);
    cr_expect_str_eq(x1, x2);
    free(x1);
    free(x2);
    hv_profile_destroy(p);
    hv_volume_destroy(v);
}

Test(profile, csv_is_written_atomically)
{
    hv_volume *v = linear_model();
    double a[3] = {0, 5, 6}, b[3] = {9, 5, 6};
    hv_profile *p;
    cr_assert_eq(hv_profile_sample(v, a, b, 10, &p), HV_OK);
    cr_expect_eq(hv_profile_write_csv(p, "/nonexistent-dir/p.csv"), HV_ERR_IO);
    cr_expect(strstr(hv_last_error(), "/nonexistent-dir/p.csv") != NULL, "%s", hv_last_error());
    char dir[512], cmd[600], path[600];
    snprintf(dir, sizeof dir, "%s", t_tmpfile("atomic"));
    snprintf(cmd, sizeof cmd, "mkdir -p '%s'", dir);
    cr_assert_eq(t_run(cmd, NULL), 0);
    snprintf(path, sizeof path, "%s/p.csv", dir);
    cr_assert_eq(hv_profile_write_csv(p, path), HV_OK);
    DIR *d = opendir(dir);
    int files = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) ++files;
    closedir(d);
    cr_expect_eq(files, 1, "temporary files left next to the CSV");
    hv_profile_destroy(p);
    hv_volume_destroy(v);
}

/* ---- plot -------------------------------------------------------------------------------- */

/* gap model: blocks at i in [0, 9] and [14, 23] (1 mm voxels, origin 0); rigid = i/23 */
static void gap_fn(int i, int j, int k, double *f)
{
    (void)j, (void)k;
    f[0] = i / 23.0;
    f[1] = 1.0 - f[0];
}

static void pixel(cairo_surface_t *sf, int x, int y, int c[3])
{
    const unsigned char *d = cairo_image_surface_get_data(sf);
    uint32_t v = ((const uint32_t *)(d + (size_t)y * cairo_image_surface_get_stride(sf)))[x];
    c[0] = (int)((v >> 16) & 255);
    c[1] = (int)((v >> 8) & 255);
    c[2] = (int)(v & 255);
}

/* a pixel within 2 rows of (x, y) close to colour rgb */
static int colour_near(cairo_surface_t *sf, int x, int y, const float rgb[4])
{
    for (int dy = -2; dy <= 2; ++dy) {
        int c[3];
        pixel(sf, x, y + dy, c);
        if (abs(c[0] - (int)lround(rgb[0] * 255)) < 40 && abs(c[1] - (int)lround(rgb[1] * 255)) < 40 &&
            abs(c[2] - (int)lround(rgb[2] * 255)) < 40)
            return 1;
    }
    return 0;
}

Test(profile, plot_shows_materials_in_their_colours_and_shades_the_outside)
{
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    hv_volume *v;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK);
    add_box(v, (int[3]){0, 0, 0}, (int[3]){9, 7, 7});
    add_box(v, (int[3]){14, 0, 0}, (int[3]){23, 7, 7});
    const char *names[2] = {"rigid", "flexible"};
    grade(v, names, 2, gap_fn, 1);
    double a[3] = {-3, 3, 4}, b[3] = {27, 3, 4};
    hv_profile *p;
    cr_assert_eq(hv_profile_sample(v, a, b, 301, &p), HV_OK);
    /* two inside runs: [-0.5, 9.5] and [13.5, 23.5] in x, i.e. t in [2.5, 12.5], [16.5, 26.5] */
    for (int i = 0; i < 301; ++i) {
        double x = -3 + 0.1 * i;
        int want = (x >= -0.5 && x <= 9.5) || (x >= 13.5 && x <= 23.5);
        if (fabs(x + 0.5) < 1e-6 || fabs(x - 9.5) < 1e-6 || fabs(x - 13.5) < 1e-6 || fabs(x - 23.5) < 1e-6) continue;
        cr_expect_eq(hv_profile_inside(p, i), want, "x = %g", x);
    }
    hv_plot *pl;
    cr_assert_eq(hv_profile_plot(p, 900, 560, &pl), HV_OK, "%s", hv_last_error());
    const char *path = t_tmpfile("profile.png");
    cr_assert_eq(hv_plot_write_png(pl, path), HV_OK, "%s", hv_last_error());
    cairo_surface_t *sf = cairo_image_surface_create_from_png(path);
    cr_assert_eq(cairo_surface_status(sf), CAIRO_STATUS_SUCCESS);
    cr_expect_eq(cairo_image_surface_get_width(sf), 900);
    cr_expect_eq(cairo_image_surface_get_height(sf), 560);
    const hv_material_table *t = hv_profile_table(p);
    float c0[4], c1[4];
    hv_material_color(t, 0, c0);
    hv_material_color(t, 1, c1);
    /* each material's line at its formula value, inside both blocks (t = distance from x=-3) */
    double ts[4] = {5.0, 10.0, 19.0, 24.0};
    for (int k = 0; k < 4; ++k) {
        double x = ts[k] - 3.0, q[2];
        cr_assert_eq(hv_plot_data_to_pixel(pl, ts[k], x / 23.0, q, NULL), HV_OK);
        cr_expect(colour_near(sf, (int)q[0], (int)q[1], c0), "rigid not drawn at t = %g", ts[k]);
        cr_assert_eq(hv_plot_data_to_pixel(pl, ts[k], 1 - x / 23.0, q, NULL), HV_OK);
        cr_expect(colour_near(sf, (int)q[0], (int)q[1], c1), "flexible not drawn at t = %g", ts[k]);
    }
    /* the gap (t in [12.5, 16.5]) is shaded and carries no line */
    double q[2];
    int c[3];
    cr_assert_eq(hv_plot_data_to_pixel(pl, 14.5, 0.5, q, NULL), HV_OK);
    pixel(sf, (int)q[0], (int)q[1], c);
    cr_expect(abs(c[0] - 219) <= 2 && abs(c[1] - 219) <= 2 && abs(c[2] - 219) <= 2, "gap not shaded: %d %d %d", c[0], c[1], c[2]);
    for (int yy = 0; yy <= 10; ++yy) {
        cr_assert_eq(hv_plot_data_to_pixel(pl, 14.5, yy / 10.0, q, NULL), HV_OK);
        cr_expect(!colour_near(sf, (int)q[0], (int)q[1], c0) && !colour_near(sf, (int)q[0], (int)q[1], c1),
                  "a line crosses the gap at y = %g", yy / 10.0);
    }
    /* inside a block at a place without lines: white */
    cr_assert_eq(hv_plot_data_to_pixel(pl, 7.3, 0.5, q, NULL), HV_OK);
    pixel(sf, (int)q[0], (int)q[1], c);
    cr_expect(c[0] == 255 && c[1] == 255 && c[2] == 255, "inside shaded: %d %d %d", c[0], c[1], c[2]);
    cairo_surface_destroy(sf);
    hv_plot_destroy(pl);
    hv_profile_destroy(p);
    hv_volume_destroy(v);
}

/* ---- errors ------------------------------------------------------------------------------ */

Test(profile, errors)
{
    hv_volume *v = linear_model();
    double a[3] = {0, 0, 0}, b[3] = {1, 1, 1}, nan3[3] = {0, NAN, 0};
    hv_profile *p = (hv_profile *)1;
    cr_expect_eq(hv_profile_sample(v, a, b, 1, &p), HV_ERR_INVALID);
    cr_expect_null(p);
    cr_expect(strstr(hv_last_error(), "at least 2") != NULL, "%s", hv_last_error());
    cr_expect_eq(hv_profile_sample(v, a, a, 10, &p), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "length 0") != NULL, "%s", hv_last_error());
    cr_expect_eq(hv_profile_sample(v, a, nan3, 10, &p), HV_ERR_INVALID);
    double far0[3] = {-1e300, 0, 0}, far1[3] = {1e300, 0, 0}; /* length overflows to inf */
    cr_expect_eq(hv_profile_sample(v, far0, far1, 10, &p), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "too long") != NULL, "%s", hv_last_error());
    cr_assert_eq(hv_profile_sample(v, a, b, 10, &p), HV_OK);
    hv_plot *pl = (hv_plot *)1;
    cr_expect_eq(hv_profile_plot(p, 10, 10, &pl), HV_ERR_INVALID);
    cr_expect_null(pl);
    hv_profile_destroy(p);
    hv_profile_destroy(NULL);
    hv_volume_destroy(v);

    /* not graded: no table */
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK);
    add_box(v, (int[3]){0, 0, 0}, (int[3]){7, 7, 7});
    grade(v, LINEAR_NAMES, 2, linear_fn, 0);
    cr_expect_eq(hv_profile_sample(v, a, b, 10, &p), HV_ERR_NOT_FOUND);
    cr_expect_null(p);
    /* a table naming a material without its grid */
    hv_material_table *t;
    cr_assert_eq(hv_material_table_create(&t), HV_OK);
    cr_assert_eq(hv_material_add(t, "soft", NULL, NULL), HV_OK);
    cr_assert_eq(hv_material_add(t, "ghost", NULL, NULL), HV_OK);
    cr_assert_eq(hv_material_table_store(v, t), HV_OK);
    hv_material_table_destroy(t);
    cr_expect_eq(hv_profile_sample(v, a, b, 10, &p), HV_ERR_BAD_INPUT);
    cr_expect(strstr(hv_last_error(), "ghost") != NULL, "%s", hv_last_error());
    hv_volume_destroy(v);
}
