/* tests/plot/test_plot.c - the cairo line plots: image size, series drawn in their colours
 * where the data mapping says, gaps, spans, markers, 1-2-5 grid lines, frame, text, legend
 * placement (never over data), determinism, SVG, argument checks and atomic output. Images
 * are read back with cairo and checked pixel by pixel; never compared byte for byte. */
#include <cairo.h>
#include <criterion/criterion.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/plot.h"
#include "support/support.h"

#define HV_MAXI(a, b) ((a) > (b) ? (a) : (b))

static const float RED[4] = {1, 0, 0, 1}, BLUE[4] = {0, 0, 1, 1};

typedef struct img {
    cairo_surface_t *sf;
    const unsigned char *data;
    int w, h, stride;
} img;

static img load(const char *path)
{
    img m;
    m.sf = cairo_image_surface_create_from_png(path);
    cr_assert_eq(cairo_surface_status(m.sf), CAIRO_STATUS_SUCCESS, "%s: %s", path,
                 cairo_status_to_string(cairo_surface_status(m.sf)));
    m.data = cairo_image_surface_get_data(m.sf);
    m.w = cairo_image_surface_get_width(m.sf);
    m.h = cairo_image_surface_get_height(m.sf);
    m.stride = cairo_image_surface_get_stride(m.sf);
    return m;
}

static void unload(img *m) { cairo_surface_destroy(m->sf); }

/* r, g, b of pixel (x, y) in 0..255 */
static void px(const img *m, int x, int y, int c[3])
{
    cr_assert(x >= 0 && x < m->w && y >= 0 && y < m->h, "pixel (%d, %d) outside %dx%d", x, y, m->w, m->h);
    uint32_t v = ((const uint32_t *)(m->data + (size_t)y * m->stride))[x];
    c[0] = (int)((v >> 16) & 255);
    c[1] = (int)((v >> 8) & 255);
    c[2] = (int)(v & 255);
}

static int near(const int c[3], int r, int g, int b, int tol)
{
    return abs(c[0] - r) <= tol && abs(c[1] - g) <= tol && abs(c[2] - b) <= tol;
}

/* Is there a pixel of colour (r,g,b) within `rows` rows of (x, y)? */
static int colour_near(const img *m, int x, int y, int rows, int r, int g, int b, int tol)
{
    for (int dy = -rows; dy <= rows; ++dy) {
        if (y + dy < 0 || y + dy >= m->h) continue;
        int c[3];
        px(m, x, y + dy, c);
        if (near(c, r, g, b, tol)) return 1;
    }
    return 0;
}

static int count_colour(const img *m, int x0, int y0, int x1, int y1, int r, int g, int b, int tol)
{
    int n = 0;
    for (int y = HV_MAXI(y0, 0); y < y1 && y < m->h; ++y)
        for (int x = HV_MAXI(x0, 0); x < x1 && x < m->w; ++x) {
            int c[3];
            px(m, x, y, c);
            n += near(c, r, g, b, tol);
        }
    return n;
}

static int count_dark(const img *m, int x0, int y0, int x1, int y1)
{
    int n = 0;
    for (int y = HV_MAXI(y0, 0); y < y1 && y < m->h; ++y)
        for (int x = HV_MAXI(x0, 0); x < x1 && x < m->w; ++x) {
            int c[3];
            px(m, x, y, c);
            n += c[0] < 100 && c[1] < 100 && c[2] < 100;
        }
    return n;
}

static void map(const hv_plot *p, double x, double y, int *ix, int *iy)
{
    double q[2];
    cr_assert_eq(hv_plot_data_to_pixel(p, x, y, q, NULL), HV_OK, "%s", hv_last_error());
    *ix = (int)floor(q[0]);
    *iy = (int)floor(q[1]);
}

/* 0..10 in 101 steps, red constant 0.25, blue constant 0.75 */
static hv_plot *two_lines(int w, int h)
{
    double x[101], a[101], b[101];
    for (int i = 0; i <= 100; ++i) {
        x[i] = i * 0.1;
        a[i] = 0.25;
        b[i] = 0.75;
    }
    hv_plot *p;
    cr_assert_eq(hv_plot_create(w, h, &p), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_plot_set_x(p, x, 101), HV_OK);
    cr_assert_eq(hv_plot_add_series(p, "red", a, RED, NULL), HV_OK);
    cr_assert_eq(hv_plot_add_series(p, "blue", b, BLUE, NULL), HV_OK);
    cr_assert_eq(hv_plot_set_title(p, "Two lines", "a subtitle"), HV_OK);
    cr_assert_eq(hv_plot_set_labels(p, "distance (mm)", "fraction"), HV_OK);
    return p;
}


Test(plot, png_has_the_requested_size)
{
    int sizes[3][2] = {{900, 560}, {640, 400}, {1201, 777}};
    for (int k = 0; k < 3; ++k) {
        hv_plot *p = two_lines(sizes[k][0], sizes[k][1]);
        const char *path = t_tmpfile("size.png");
        cr_assert_eq(hv_plot_write_png(p, path), HV_OK, "%s", hv_last_error());
        img m = load(path);
        cr_expect_eq(m.w, sizes[k][0]);
        cr_expect_eq(m.h, sizes[k][1]);
        unload(&m);
        hv_plot_destroy(p);
    }
}

Test(plot, series_are_drawn_in_their_colours_where_the_mapping_says)
{
    hv_plot *p = two_lines(900, 560);
    const char *path = t_tmpfile("lines.png");
    cr_assert_eq(hv_plot_write_png(p, path), HV_OK, "%s", hv_last_error());
    img m = load(path);
    /* along the whole line, every column has the series colour at the mapped row: a legend
     * or label drawn over the data would break this */
    int x0, x1, yr, yb, dummy;
    map(p, 0.05, 0.25, &x0, &yr);
    map(p, 9.95, 0.75, &x1, &yb);
    for (int x = x0; x <= x1; ++x) {
        cr_assert(colour_near(&m, x, yr, 1, 255, 0, 0, 40), "no red line at column %d row %d", x, yr);
        cr_assert(colour_near(&m, x, yb, 1, 0, 0, 255, 40), "no blue line at column %d row %d", x, yb);
    }
    /* and nowhere else in the middle of the plot: the row halfway between is background */
    int ym;
    map(p, 5.0, 0.5, &dummy, &ym);
    cr_expect_eq(count_colour(&m, x0, ym - 3, x1, ym + 4, 255, 0, 0, 60), 0);
    cr_expect_eq(count_colour(&m, x0, ym - 3, x1, ym + 4, 0, 0, 255, 60), 0);
    unload(&m);
    hv_plot_destroy(p);
}

Test(plot, frame_ticks_grid_and_text_are_drawn)
{
    hv_plot *p = two_lines(900, 560);
    const char *path = t_tmpfile("axes.png");
    cr_assert_eq(hv_plot_write_png(p, path), HV_OK, "%s", hv_last_error());
    double q[2], box[4];
    cr_assert_eq(hv_plot_data_to_pixel(p, 0, 0, q, box), HV_OK);
    img m = load(path);
    int l = (int)box[0], t = (int)box[1], r = (int)box[2], b = (int)box[3];
    cr_assert(l > 30 && t > 30 && r < m.w - 5 && b < m.h - 30, "plot area %d %d %d %d", l, t, r, b);
    /* frame: dark left column and bottom row over their whole length */
    for (int y = t; y < b; ++y) {
        int c[3];
        px(&m, l, y, c);
        cr_assert(c[0] < 80 && c[1] < 80 && c[2] < 80, "left frame missing at row %d", y);
    }
    for (int x = l; x < r; ++x) {
        int c[3];
        px(&m, x, b - 1, c);
        cr_assert(c[0] < 80 && c[1] < 80 && c[2] < 80, "bottom frame missing at column %d", x);
    }
    /* y fixed to [0, 1] with room above and below: 0 and 1 lie strictly inside the frame */
    int ix, iy0, iy1;
    map(p, 0, 0, &ix, &iy0);
    map(p, 0, 1, &ix, &iy1);
    cr_expect(iy0 < b - 3 && iy1 > t + 3, "0 at row %d, 1 at row %d, frame %d..%d", iy0, iy1, t, b);
    /* 1-2-5 ticks: light grid rows at 0.2, 0.4, ... (step 0.2 for a 460 px tall area), none at
     * 0.1 or 0.3; grid columns at every integer x (step 1), none at 3.5 */
    int gx, gy, c[3];
    for (int k = 0; k <= 5; ++k) {
        map(p, 3.5, 0.2 * k, &gx, &gy);
        cr_expect(colour_near(&m, gx, gy, 1, 224, 224, 224, 6), "no grid line at y = %g", 0.2 * k);
    }
    map(p, 3.5, 0.1, &gx, &gy);
    cr_expect(!colour_near(&m, gx, gy, 2, 224, 224, 224, 6), "grid line at y = 0.1");
    for (int k = 1; k <= 9; ++k) {
        map(p, (double)k, 0.5, &gx, &gy);
        int hit = 0;
        for (int dx = -1; dx <= 1; ++dx) {
            px(&m, gx + dx, gy, c);
            hit |= near(c, 224, 224, 224, 6);
        }
        cr_expect(hit, "no grid line at x = %d", k);
    }
    map(p, 3.5, 0.5, &gx, &gy);
    px(&m, gx, gy, c);
    cr_expect(near(c, 255, 255, 255, 0), "background at x = 3.5 is %d %d %d", c[0], c[1], c[2]);
    /* text: tick labels left of and below the frame, the title above, the y label at the far
     * left: enough dark pixels in each region (fails when no font renders) */
    cr_expect_gt(count_dark(&m, 0, t, l - 8, b), 150, "no y tick labels");
    cr_expect_gt(count_dark(&m, l, b + 6, r, m.h), 150, "no x tick labels");
    cr_expect_gt(count_dark(&m, l, 0, r, t - 2), 150, "no title");
    cr_expect_gt(count_dark(&m, 0, t, 22, b), 40, "no y label");
    unload(&m);
    hv_plot_destroy(p);
}

Test(plot, nan_leaves_a_gap_and_isolated_samples_are_dots)
{
    double x[101], y[101];
    for (int i = 0; i <= 100; ++i) {
        x[i] = i * 0.1;
        y[i] = (i > 40 && i < 60) || (i > 80 && i != 90) ? NAN : 0.5;
    }
    hv_plot *p;
    cr_assert_eq(hv_plot_create(900, 560, &p), HV_OK);
    cr_assert_eq(hv_plot_set_x(p, x, 101), HV_OK);
    cr_assert_eq(hv_plot_add_series(p, "gappy", y, RED, NULL), HV_OK);
    const char *path = t_tmpfile("gap.png");
    cr_assert_eq(hv_plot_write_png(p, path), HV_OK, "%s", hv_last_error());
    img m = load(path);
    int xa, xb, y5, xd;
    map(p, 4.3, 0.5, &xa, &y5);
    map(p, 5.7, 0.5, &xb, &y5);
    cr_expect_eq(count_colour(&m, xa, y5 - 4, xb, y5 + 5, 255, 0, 0, 80), 0, "red inside the gap");
    map(p, 2.0, 0.5, &xa, &y5);
    cr_expect(colour_near(&m, xa, y5, 1, 255, 0, 0, 40), "no line before the gap");
    map(p, 9.0, 0.5, &xd, &y5);
    cr_expect_gt(count_colour(&m, xd - 2, y5 - 2, xd + 3, y5 + 3, 255, 0, 0, 60), 0, "isolated sample not drawn");
    map(p, 9.5, 0.5, &xa, &y5);
    cr_expect_eq(count_colour(&m, xa - 2, y5 - 2, xa + 3, y5 + 3, 255, 0, 0, 80), 0, "red after the dot");
    unload(&m);
    hv_plot_destroy(p);
}

Test(plot, spans_and_markers)
{
    hv_plot *p = two_lines(900, 560);
    double top[101];
    for (int i = 0; i <= 100; ++i) top[i] = 1.0;
    const float green[4] = {0, 0.5f, 0, 1};
    cr_assert_eq(hv_plot_add_series(p, "top", top, green, NULL), HV_OK);
    cr_assert_eq(hv_plot_add_span(p, 3.0, 2.0, "outside"), HV_OK); /* swapped ends */
    cr_assert_eq(hv_plot_add_span(p, 6.2, 6.8, "outside"), HV_OK);
    cr_assert_eq(hv_plot_add_marker(p, 7.3, "d-"), HV_OK);
    cr_assert_eq(hv_plot_add_marker(p, 42.0, "never"), HV_OK); /* outside the x range */
    const char *path = t_tmpfile("spans.png");
    cr_assert_eq(hv_plot_write_png(p, path), HV_OK, "%s", hv_last_error());
    img m = load(path);
    int x, y, c[3];
    map(p, 2.5, 0.5, &x, &y);
    px(&m, x, y, c);
    cr_expect(near(c, 219, 219, 219, 2), "span colour %d %d %d", c[0], c[1], c[2]);
    map(p, 6.5, 0.1, &x, &y);
    px(&m, x, y, c);
    cr_expect(near(c, 219, 219, 219, 2), "second span colour %d %d %d", c[0], c[1], c[2]);
    map(p, 4.5, 0.5, &x, &y);
    px(&m, x, y, c);
    cr_expect(near(c, 255, 255, 255, 0), "no span at 4.5: %d %d %d", c[0], c[1], c[2]);
    /* the lines are drawn over the span */
    map(p, 2.5, 0.25, &x, &y);
    cr_expect(colour_near(&m, x, y, 1, 255, 0, 0, 40), "line hidden by the span");
    /* the dashed marker: dark grey pixels down its column, but not all of them (dashes) */
    double q[2], box[4];
    cr_assert_eq(hv_plot_data_to_pixel(p, 7.3, 0.5, q, box), HV_OK);
    int mx = (int)floor(q[0] + 0.5) - 0, dark = 0, rows = 0;
    for (int yy = (int)box[1] + 40; yy < (int)box[3] - 2; ++yy) {
        int best = 0;
        for (int dx = -1; dx <= 0; ++dx) {
            px(&m, mx + dx, yy, c);
            best |= near(c, 77, 77, 77, 25);
        }
        dark += best;
        ++rows;
    }
    cr_expect(dark > rows / 3 && dark < rows, "marker column: %d of %d rows dark", dark, rows);
    /* its label is drawn above the plot area, centred on the line, so it hides no data: the
     * line at y = 1 runs unbroken under it */
    int lab = 0;
    for (int yy = (int)box[1] - 18; yy < (int)box[1] - 1; ++yy)
        for (int xx = mx - 12; xx <= mx + 12; ++xx) {
            px(&m, xx, yy, c);
            lab += c[0] < 150 && c[1] < 150 && c[2] < 150;
        }
    cr_expect_gt(lab, 10, "no marker label above the plot area");
    int x0, x1, yt;
    map(p, 0.05, 1.0, &x0, &yt);
    map(p, 9.95, 1.0, &x1, &yt);
    for (int xx = x0; xx <= x1; ++xx) cr_assert(colour_near(&m, xx, yt, 1, 0, 128, 0, 40), "line at 1 hidden at column %d", xx);
    unload(&m);
    hv_plot_destroy(p);
}

Test(plot, legend_in_the_series_colours_avoids_the_data)
{
    hv_plot *p = two_lines(900, 560);
    const char *path = t_tmpfile("legend.png");
    cr_assert_eq(hv_plot_write_png(p, path), HV_OK, "%s", hv_last_error());
    img m = load(path);
    double q[2], box[4];
    cr_assert_eq(hv_plot_data_to_pixel(p, 0, 0, q, box), HV_OK);
    /* lines at 0.25 and 0.75 leave the upper right corner free: the legend goes there, with
     * swatches in the series colours */
    int r = (int)box[2], t = (int)box[1], yb;
    int dummy;
    map(p, 5, 0.75, &dummy, &yb);
    cr_expect_gt(count_colour(&m, r - 220, t, r, yb - 6, 255, 0, 0, 20), 20, "no red swatch in the upper right");
    cr_expect_gt(count_colour(&m, r - 220, t, r, yb - 6, 0, 0, 255, 20), 20, "no blue swatch in the upper right");
    unload(&m);
    hv_plot_destroy(p);
}

Test(plot, legend_moves_outside_when_every_place_covers_data)
{
    /* zig-zags filling the whole area: no inside place is free */
    enum { N = 401 };
    double x[N], y[4][N];
    for (int i = 0; i < N; ++i) {
        x[i] = i;
        for (int s = 0; s < 4; ++s) y[s][i] = (i + s * 3) % 12 < 6 ? 0.02 + s * 0.01 : 0.98 - s * 0.01;
    }
    hv_plot *p;
    cr_assert_eq(hv_plot_create(900, 560, &p), HV_OK);
    cr_assert_eq(hv_plot_set_x(p, x, N), HV_OK);
    const float cols[4][4] = {{1, 0, 0, 1}, {0, 0, 1, 1}, {0, 0.6f, 0, 1}, {0.5f, 0, 0.5f, 1}};
    const char *names[4] = {"alpha", "beta", "gamma", "delta"};
    for (int s = 0; s < 4; ++s) cr_assert_eq(hv_plot_add_series(p, names[s], y[s], cols[s], NULL), HV_OK);
    const char *path = t_tmpfile("outside.png");
    cr_assert_eq(hv_plot_write_png(p, path), HV_OK, "%s", hv_last_error());
    double q[2], box[4];
    cr_assert_eq(hv_plot_data_to_pixel(p, 0, 0, q, box), HV_OK);
    img m = load(path);
    cr_expect_lt(box[2], m.w - 100, "plot area not narrowed for the legend (right edge %g)", box[2]);
    int r = (int)box[2];
    cr_expect_gt(count_colour(&m, r + 2, 0, m.w, m.h, 255, 0, 0, 20), 20, "no legend right of the plot");
    cr_expect_gt(count_colour(&m, r + 2, 0, m.w, m.h, 0, 0, 255, 20), 20, "no legend right of the plot");
    unload(&m);
    hv_plot_destroy(p);
}

Test(plot, light_colours_get_an_outline)
{
    double x[11], y[11];
    for (int i = 0; i <= 10; ++i) {
        x[i] = i;
        y[i] = 0.5;
    }
    const float white[4] = {1, 1, 1, 1};
    hv_plot *p;
    cr_assert_eq(hv_plot_create(900, 560, &p), HV_OK);
    cr_assert_eq(hv_plot_set_x(p, x, 11), HV_OK);
    cr_assert_eq(hv_plot_add_series(p, "white", y, white, NULL), HV_OK);
    const char *path = t_tmpfile("white.png");
    cr_assert_eq(hv_plot_write_png(p, path), HV_OK);
    img m = load(path);
    int ix, iy;
    map(p, 5.5, 0.5, &ix, &iy);
    int grey = 0;
    for (int dy = -4; dy <= 4; ++dy) {
        int c[3];
        px(&m, ix, iy + dy, c);
        grey += c[0] < 200;
    }
    cr_expect_geq(grey, 1, "a white line on white is invisible without its outline");
    unload(&m);
    hv_plot_destroy(p);
}

Test(plot, auto_y_range_uses_nice_ticks)
{
    double x[3] = {0, 1, 2}, y[3] = {3.2, 17.0, 36.9};
    hv_plot *p;
    cr_assert_eq(hv_plot_create(900, 560, &p), HV_OK);
    cr_assert_eq(hv_plot_set_x(p, x, 3), HV_OK);
    cr_assert_eq(hv_plot_add_series(p, "y", y, RED, NULL), HV_OK);
    cr_assert_eq(hv_plot_set_y_range(p, NAN, NAN), HV_OK);
    double q0[2], q1[2], box[4];
    cr_assert_eq(hv_plot_data_to_pixel(p, 0, 3.2, q0, box), HV_OK);
    cr_assert_eq(hv_plot_data_to_pixel(p, 2, 36.9, q1, NULL), HV_OK);
    /* the data fill the range [0, 40] widened to 5-multiples, so both ends are inside and
     * 40 is near the top of the area, 0 near the bottom */
    double z[2], f[2];
    cr_assert_eq(hv_plot_data_to_pixel(p, 0, 0, z, NULL), HV_OK);
    cr_assert_eq(hv_plot_data_to_pixel(p, 0, 40, f, NULL), HV_OK);
    double h = box[3] - box[1];
    cr_expect(fabs((box[3] - z[1]) - 0.03 / 1.06 * h) < 0.5, "0 at %g, area %g..%g", z[1], box[1], box[3]);
    cr_expect(fabs((f[1] - box[1]) - 0.03 / 1.06 * h) < 0.5, "40 at %g, area %g..%g", f[1], box[1], box[3]);
    hv_plot_destroy(p);
}

Test(plot, output_is_deterministic_and_scales_with_size)
{
    hv_plot *p = two_lines(900, 560), *q = two_lines(1800, 1120);
    const char *a = t_tmpfile("d1.png"), *b = t_tmpfile("d2.png");
    cr_assert_eq(hv_plot_write_png(p, a), HV_OK);
    cr_assert_eq(hv_plot_write_png(p, b), HV_OK);
    img ma = load(a), mb = load(b);
    cr_expect_eq(memcmp(ma.data, mb.data, (size_t)ma.stride * ma.h), 0, "two renderings differ");
    unload(&ma);
    unload(&mb);
    double z[2], b1[4], b2[4];
    cr_assert_eq(hv_plot_data_to_pixel(p, 0, 0, z, b1), HV_OK);
    cr_assert_eq(hv_plot_data_to_pixel(q, 0, 0, z, b2), HV_OK);
    for (int k = 0; k < 4; ++k) cr_expect(fabs(b2[k] - 2 * b1[k]) <= 2.0, "box[%d]: %g vs 2 x %g", k, b2[k], b1[k]);
    hv_plot_destroy(p);
    hv_plot_destroy(q);
}

Test(plot, svg_output)
{
    hv_plot *p = two_lines(900, 560);
    const char *path = t_tmpfile("plot.svg");
    cr_assert_eq(hv_plot_write_svg(p, path), HV_OK, "%s", hv_last_error());
    char *text = NULL;
    char cmd[600];
    snprintf(cmd, sizeof cmd, "cat '%s'", path);
    cr_assert_eq(t_run(cmd, &text), 0);
    cr_expect(strstr(text, "<svg") != NULL);
    cr_expect(strstr(text, "width=\"900") != NULL, "width not 900");
    cr_expect(strstr(text, "rgb(100%,0%,0%)") != NULL, "no red stroke");
    free(text);
    hv_plot_destroy(p);
}

Test(plot, bad_arguments_are_rejected)
{
    hv_plot *p = NULL;
    double x[3] = {0, 1, 2}, y[3] = {0, 0.5, 1}, bad[3] = {0, INFINITY, 1};
    cr_expect_eq(hv_plot_create(50, 500, &p), HV_ERR_INVALID);
    cr_expect_null(p);
    cr_expect_eq(hv_plot_create(900, 9000, &p), HV_ERR_INVALID);
    cr_assert_eq(hv_plot_create(900, 560, &p), HV_OK);
    cr_expect_eq(hv_plot_add_series(p, "early", y, RED, NULL), HV_ERR_INVALID);
    cr_expect_eq(hv_plot_write_png(p, t_tmpfile("empty.png")), HV_ERR_INVALID);
    cr_expect(!t_exists(t_tmpfile("empty.png")));
    double xn[2] = {0, NAN};
    cr_expect_eq(hv_plot_set_x(p, xn, 2), HV_ERR_INVALID);
    cr_expect_eq(hv_plot_set_x(p, x, 0), HV_ERR_INVALID);
    double wide[2] = {-1.7e308, 1.7e308};
    cr_expect_eq(hv_plot_set_x(p, wide, 2), HV_ERR_INVALID);
    cr_expect_eq(hv_plot_set_y_range(p, -1.7e308, 1.7e308), HV_ERR_INVALID);
    cr_assert_eq(hv_plot_set_x(p, x, 3), HV_OK);
    cr_expect_eq(hv_plot_add_series(p, "inf", bad, RED, NULL), HV_ERR_INVALID);
    const float over[4] = {1.5f, 0, 0, 1};
    cr_expect_eq(hv_plot_add_series(p, "over", y, over, NULL), HV_ERR_INVALID);
    cr_expect_eq(hv_plot_add_series(p, "bad \xff utf8", y, RED, NULL), HV_ERR_INVALID);
    cr_expect_eq(hv_plot_set_title(p, "\xc3\x28", NULL), HV_ERR_INVALID);
    cr_expect_eq(hv_plot_set_title(p, "ok \xce\xbc" "m", "\xed\xa0\x80"), HV_ERR_INVALID); /* surrogate */
    cr_expect_eq(hv_plot_set_y_range(p, 1, 0), HV_ERR_INVALID);
    cr_expect_eq(hv_plot_set_y_range(p, 0, INFINITY), HV_ERR_INVALID);
    cr_expect_eq(hv_plot_add_marker(p, NAN, "x"), HV_ERR_INVALID);
    cr_expect_eq(hv_plot_add_span(p, 0, INFINITY, "x"), HV_ERR_INVALID);
    int idx = -1;
    cr_assert_eq(hv_plot_add_series(p, "ok", y, RED, &idx), HV_OK);
    cr_expect_eq(idx, 0);
    cr_expect_eq(hv_plot_set_series_dashed(p, 1, 1), HV_ERR_INVALID);
    cr_expect_eq(hv_plot_set_series_dashed(p, 0, 1), HV_OK);
    /* the error message names the problem */
    cr_expect_eq(hv_plot_set_y_range(p, 2, 2), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "lo < hi") != NULL, "%s", hv_last_error());
    hv_plot_destroy(p);
    hv_plot_destroy(NULL);
}

Test(plot, writes_atomically)
{
    hv_plot *p = two_lines(900, 560);
    cr_expect_eq(hv_plot_write_png(p, "/nonexistent-dir/x.png"), HV_ERR_IO);
    cr_expect(strstr(hv_last_error(), "/nonexistent-dir/x.png") != NULL, "%s", hv_last_error());
    /* success leaves exactly the file, no temporary next to it */
    char dir[512];
    snprintf(dir, sizeof dir, "%s", t_tmpfile("atomic"));
    char cmd[600];
    snprintf(cmd, sizeof cmd, "mkdir -p '%s'", dir);
    cr_assert_eq(t_run(cmd, NULL), 0);
    char path[600];
    snprintf(path, sizeof path, "%s/plot.png", dir);
    cr_assert_eq(hv_plot_write_png(p, path), HV_OK);
    cr_assert_eq(hv_plot_write_png(p, path), HV_OK); /* replacing an existing file */
    DIR *d = opendir(dir);
    cr_assert_not_null(d);
    int files = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            ++files;
            cr_expect_str_eq(e->d_name, "plot.png");
        }
    closedir(d);
    cr_expect_eq(files, 1);
    hv_plot_destroy(p);
}

Test(plot, null_keeps_texts_and_empty_removes_them)
{
    hv_plot *p = two_lines(900, 560);
    double q[2], both[4], title_only[4], none[4], again[4];
    cr_assert_eq(hv_plot_data_to_pixel(p, 0, 0, q, both), HV_OK);
    cr_assert_eq(hv_plot_set_title(p, NULL, ""), HV_OK); /* keep the title, drop the subtitle */
    cr_assert_eq(hv_plot_data_to_pixel(p, 0, 0, q, title_only), HV_OK);
    cr_assert_eq(hv_plot_set_title(p, "", NULL), HV_OK);
    cr_assert_eq(hv_plot_data_to_pixel(p, 0, 0, q, none), HV_OK);
    cr_expect(both[1] > title_only[1] && title_only[1] > none[1], "plot tops %g %g %g", both[1], title_only[1], none[1]);
    cr_assert_eq(hv_plot_set_labels(p, NULL, ""), HV_OK); /* y label gone: more room on the left */
    cr_assert_eq(hv_plot_data_to_pixel(p, 0, 0, q, again), HV_OK);
    cr_expect(again[0] < none[0] && again[3] == none[3], "left %g vs %g, bottom %g vs %g", again[0], none[0], again[3], none[3]);
    hv_plot_destroy(p);
}

Test(plot, extreme_values_do_not_break_drawing)
{
    double x[4] = {0, 1, 2, 3}, y[4] = {0.5, 1e300, -1e300, 0.5}, big[4] = {-1.7e308, 0, 1.7e308, 1};
    hv_plot *p;
    cr_assert_eq(hv_plot_create(300, 200, &p), HV_OK);
    cr_assert_eq(hv_plot_set_x(p, x, 4), HV_OK);
    cr_assert_eq(hv_plot_add_series(p, "spiky", y, RED, NULL), HV_OK);
    cr_assert_eq(hv_plot_add_series(p, "huge", big, BLUE, NULL), HV_OK);
    cr_expect_eq(hv_plot_write_png(p, t_tmpfile("extreme.png")), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_plot_set_y_range(p, NAN, NAN), HV_OK);
    cr_expect_eq(hv_plot_write_png(p, t_tmpfile("extreme_auto.png")), HV_OK, "%s", hv_last_error());
    img m = load(t_tmpfile("extreme_auto.png"));
    cr_expect_eq(m.w, 300);
    unload(&m);
    hv_plot_destroy(p);
}

/* A right-hand axis over [0, 1000] next to the left one over [0, 1]: a series of 1000 * a, put
 * on it, lies exactly on the left mapping of a, drawn where that mapping says; tick labels appear
 * right of the frame; the axis and series calls check their arguments. */
Test(plot, right_axis_series_follow_their_own_range)
{
    double x[101], a[101], big[101];
    for (int i = 0; i <= 100; ++i) {
        x[i] = i * 0.1;
        a[i] = 0.2 + 0.006 * i;
        big[i] = 1000 * (0.8 - 0.006 * i); /* falls from 800 to 200: crosses a at x = 5 */
    }
    hv_plot *p;
    cr_assert_eq(hv_plot_create(900, 560, &p), HV_OK);
    cr_assert_eq(hv_plot_set_x(p, x, 101), HV_OK);
    int ia, ib;
    cr_assert_eq(hv_plot_add_series(p, "left", a, RED, &ia), HV_OK);
    cr_assert_eq(hv_plot_add_series(p, "right", big, BLUE, &ib), HV_OK);
    cr_assert_eq(hv_plot_set_series_right(p, ib, 1), HV_ERR_INVALID); /* no right axis yet */
    cr_assert_eq(hv_plot_set_right_axis(p, "modulus (MPa)", 5, 5), HV_ERR_INVALID);
    cr_assert_eq(hv_plot_set_right_axis(p, "modulus (MPa)", 0, 1000), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_plot_set_series_right(p, 7, 1), HV_ERR_INVALID);
    cr_assert_eq(hv_plot_set_series_right(p, ib, 1), HV_OK);
    const char *path = t_tmpfile("right.png");
    cr_assert_eq(hv_plot_write_png(p, path), HV_OK, "%s", hv_last_error());
    img m = load(path);
    double box[4], q[2];
    cr_assert_eq(hv_plot_data_to_pixel(p, 1, 0.8 - 0.06, q, box), HV_OK);
    /* the blue series at x = 1, 2, 7, 8 sits where the left mapping puts its value / 1000 */
    for (int k = 0; k < 4; ++k) {
        double xs = k < 2 ? 1 + k : 5 + k; /* 1, 2, 7, 8 */
        int ix, iy;
        map(p, xs, 0.8 - 0.06 * xs, &ix, &iy);
        cr_assert(colour_near(&m, ix, iy, 2, 0, 0, 255, 40), "no blue at x = %g (pixel %d, %d)", xs, ix, iy);
        map(p, xs, 0.2 + 0.06 * xs, &ix, &iy);
        cr_assert(colour_near(&m, ix, iy, 2, 255, 0, 0, 40), "no red at x = %g (pixel %d, %d)", xs, ix, iy);
    }
    /* tick labels right of the frame: dark text in the strip beyond the right edge */
    cr_assert_gt(count_dark(&m, (int)box[2] + 8, (int)box[1], m.w - 1, (int)box[3]), 50);
    unload(&m);
    /* without the right axis the blue series leaves the [0, 1] view: nothing blue at x = 8 */
    cr_assert_eq(hv_plot_set_series_right(p, ib, 0), HV_OK);
    cr_assert_eq(hv_plot_write_png(p, path), HV_OK);
    m = load(path);
    int ix, iy;
    map(p, 8, 0.8 - 0.48, &ix, &iy);
    cr_assert(!colour_near(&m, ix, iy, 2, 0, 0, 255, 40), "blue drawn at the left mapping of its value / 1000");
    unload(&m);
    hv_plot_destroy(p);
}
