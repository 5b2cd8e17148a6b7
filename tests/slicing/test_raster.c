/* tests/slicing/test_raster.c - contour rasterisation at printer resolution: centre sampling
 * against point-in-polygon at every pixel centre (random star polygons), the half-open rule
 * on shared edges, nonzero vs even-odd on overlapping shells, Wu's distance threshold. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/layers.h"
#include "hovox/slice.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static uint64_t g_rng = 0x9e3779b97f4a7c15ull;
static double urand(void)
{
    g_rng ^= g_rng << 13;
    g_rng ^= g_rng >> 7;
    g_rng ^= g_rng << 17;
    return (double)(g_rng >> 11) * (1.0 / 9007199254740992.0);
}

/* A prism over a polygon that is star-shaped around (cx, cy): fan caps, quad sides. */
static hv_mesh *prism(const double *xy, int n, double cx, double cy, double z0, double z1)
{
    float *v = malloc(sizeof(float) * 3 * (2 * n + 2));
    uint32_t *f = malloc(sizeof(uint32_t) * 3 * 4 * n);
    for (int i = 0; i < n; ++i) {
        v[3 * i] = (float)xy[2 * i];
        v[3 * i + 1] = (float)xy[2 * i + 1];
        v[3 * i + 2] = (float)z0;
        v[3 * (n + i)] = (float)xy[2 * i];
        v[3 * (n + i) + 1] = (float)xy[2 * i + 1];
        v[3 * (n + i) + 2] = (float)z1;
    }
    float c[6] = {(float)cx, (float)cy, (float)z0, (float)cx, (float)cy, (float)z1};
    memcpy(v + 3 * 2 * n, c, sizeof c);
    uint32_t cb = (uint32_t)(2 * n), ct = cb + 1;
    size_t k = 0;
    for (int i = 0; i < n; ++i) {
        uint32_t a = (uint32_t)i, b = (uint32_t)((i + 1) % n), A = a + (uint32_t)n, B = b + (uint32_t)n;
        uint32_t t[4][3] = {{cb, b, a}, {ct, A, B}, {a, b, B}, {a, B, A}};
        for (int q = 0; q < 4; ++q)
            for (int e = 0; e < 3; ++e) f[k++] = t[q][e];
    }
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_create(v, (size_t)(2 * n + 2), f, (size_t)(4 * n), &m), HV_OK, "%s", hv_last_error());
    free(v);
    free(f);
    return m;
}

static hv_slice *slice_mesh(const hv_mesh *m, double z)
{
    hv_slicer *s = NULL;
    cr_assert_eq(hv_slicer_create(m, NULL, &s), HV_OK, "%s", hv_last_error());
    hv_slice *sl = NULL;
    cr_assert_eq(hv_slicer_slice(s, z, NULL, &sl), HV_OK);
    hv_slicer_destroy(s);
    return sl;
}

/* Independent point-in-polygon: winding number by signed crossings of the ray to +x. */
static int winding(const hv_slice *sl, double px, double py)
{
    int w = 0;
    const hv_slice_loop *L = hv_slice_loops(sl);
    for (size_t l = 0; l < hv_slice_loop_count(sl); ++l) {
        if (!L[l].closed) continue;
        for (size_t i = 0; i < L[l].count; ++i) {
            const double *a = L[l].xy + 2 * i, *b = L[l].xy + 2 * ((i + 1) % L[l].count);
            if ((a[1] <= py) != (b[1] <= py)) {
                double x = a[0] + (py - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
                if (x > px) w += b[1] > a[1] ? 1 : -1;
            }
        }
    }
    return w;
}

static double edge_distance(const hv_slice *sl, double px, double py)
{
    double best = INFINITY;
    const hv_slice_loop *L = hv_slice_loops(sl);
    for (size_t l = 0; l < hv_slice_loop_count(sl); ++l)
        for (size_t i = 0; i < L[l].count; ++i) {
            const double *a = L[l].xy + 2 * i, *b = L[l].xy + 2 * ((i + 1) % L[l].count);
            double dx = b[0] - a[0], dy = b[1] - a[1], t = ((px - a[0]) * dx + (py - a[1]) * dy) / (dx * dx + dy * dy);
            t = fmin(1, fmax(0, t));
            best = fmin(best, hypot(px - a[0] - t * dx, py - a[1] - t * dy));
        }
    return best;
}

Test(raster, random_star_polygons_match_point_in_polygon)
{
    for (int t = 0; t < 20; ++t) {
        int n = 5 + (int)(urand() * 40);
        double *xy = malloc(sizeof(double) * 2 * n);
        for (int i = 0; i < n; ++i) {
            double ang = 2 * M_PI * (i + 0.3 * urand()) / n, r = 2 + 6 * urand();
            xy[2 * i] = 10 + r * cos(ang);
            xy[2 * i + 1] = 10 + r * sin(ang);
        }
        hv_mesh *m = prism(xy, n, 10, 10, 0, 1);
        hv_slice *sl = slice_mesh(m, 0.5);
        hv_raster_grid g = {137, 91, {1.013, 18.77}, {0.131, -0.187}};
        uint8_t *mask = malloc((size_t)g.width * g.height);
        cr_assert_eq(hv_slice_rasterize(sl, &g, HV_FILL_NONZERO, 0, mask, 0), HV_OK);
        int bad = 0, inside = 0;
        for (int r = 0; r < g.height; ++r)
            for (int c = 0; c < g.width; ++c) {
                double x = g.origin[0] + (c + 0.5) * g.pixel[0], y = g.origin[1] + (r + 0.5) * g.pixel[1];
                if (edge_distance(sl, x, y) < 1e-9) continue; /* on an edge: either side is right */
                int want = winding(sl, x, y) != 0;
                inside += want;
                bad += want != mask[r * g.width + c];
            }
        cr_expect_eq(bad, 0, "polygon %d (%d vertices): %d of %d pixels differ", t, n, bad, inside);
        cr_expect(inside > 100);
        free(mask);
        hv_slice_destroy(sl);
        hv_mesh_destroy(m);
        free(xy);
    }
}

static hv_mesh *two_boxes(const double lo1[3], const double hi1[3], const double lo2[3], const double hi2[3])
{
    hv_mesh *a = NULL, *b = NULL, *m = NULL;
    cr_assert_eq(hv_generate_box(lo1, hi1, &a), HV_OK);
    cr_assert_eq(hv_generate_box(lo2, hi2, &b), HV_OK);
    size_t na = hv_mesh_vertex_count(a), nb = hv_mesh_vertex_count(b);
    size_t fa = hv_mesh_facet_count(a), fb = hv_mesh_facet_count(b);
    float *v = malloc(sizeof(float) * 3 * (na + nb));
    uint32_t *f = malloc(sizeof(uint32_t) * 3 * (fa + fb));
    memcpy(v, hv_mesh_vertices(a), sizeof(float) * 3 * na);
    memcpy(v + 3 * na, hv_mesh_vertices(b), sizeof(float) * 3 * nb);
    memcpy(f, hv_mesh_facets(a), sizeof(uint32_t) * 3 * fa);
    const uint32_t *fbp = hv_mesh_facets(b);
    for (size_t i = 0; i < 3 * fb; ++i) f[3 * fa + i] = fbp[i] + (uint32_t)na;
    cr_assert_eq(hv_mesh_create(v, na + nb, f, fa + fb, &m), HV_OK);
    free(v);
    free(f);
    hv_mesh_destroy(a);
    hv_mesh_destroy(b);
    return m;
}

Test(raster, nonzero_unites_evenodd_excludes_overlaps)
{
    double lo1[3] = {0, 0, 0}, hi1[3] = {4, 4, 1}, lo2[3] = {2, 2, 0}, hi2[3] = {6, 6, 1};
    hv_mesh *m = two_boxes(lo1, hi1, lo2, hi2);
    hv_slice *sl = slice_mesh(m, 0.5);
    hv_raster_grid g = {70, 70, {-0.5, 6.5}, {0.1, -0.1}};
    uint8_t nz[4900], eo[4900];
    cr_assert_eq(hv_slice_rasterize(sl, &g, HV_FILL_NONZERO, 0, nz, 0), HV_OK);
    cr_assert_eq(hv_slice_rasterize(sl, &g, HV_FILL_EVENODD, 0, eo, 0), HV_OK);
    int bad = 0;
    for (int r = 0; r < 70; ++r)
        for (int c = 0; c < 70; ++c) {
            double x = g.origin[0] + (c + 0.5) * 0.1, y = g.origin[1] - (r + 0.5) * 0.1;
            int in1 = x >= 0 && x < 4 && y >= 0 && y < 4, in2 = x >= 2 && x < 6 && y >= 2 && y < 6;
            bad += nz[r * 70 + c] != (in1 || in2);
            bad += eo[r * 70 + c] != (in1 != in2);
        }
    cr_expect_eq(bad, 0, "%d pixels differ from union / exclusive or", bad);
    hv_slice_destroy(sl);
    hv_mesh_destroy(m);
}

Test(raster, shared_edge_on_pixel_centres_is_claimed_once)
{
    /* two boxes meeting at x = 2.0625, a column of pixel centres (all values exact in float
     * and double): even-odd would open a gap there if both loops claimed it */
    double lo1[3] = {0.0625, 0.0625, 0}, hi1[3] = {2.0625, 1.0625, 1};
    double lo2[3] = {2.0625, 0.0625, 0}, hi2[3] = {4.0625, 1.0625, 1};
    hv_mesh *m = two_boxes(lo1, hi1, lo2, hi2);
    hv_slice *sl = slice_mesh(m, 0.5);
    hv_raster_grid g = {40, 16, {-0.5, 1.5}, {0.125, -0.125}};
    uint8_t eo[640], nz[640];
    cr_assert_eq(hv_slice_rasterize(sl, &g, HV_FILL_EVENODD, 0, eo, 0), HV_OK);
    cr_assert_eq(hv_slice_rasterize(sl, &g, HV_FILL_NONZERO, 0, nz, 0), HV_OK);
    cr_expect_eq(memcmp(eo, nz, sizeof eo), 0, "even-odd differs from nonzero on touching boxes");
    int n = 0, bad = 0;
    for (int r = 0; r < 16; ++r)
        for (int c = 0; c < 40; ++c) {
            double x = -0.5 + (c + 0.5) * 0.125, y = 1.5 - (r + 0.5) * 0.125;
            /* half-open: x in [0.0625, 4.0625), y in [0.0625, 1.0625) */
            int want = x >= 0.0625 && x < 4.0625 && y >= 0.0625 && y < 1.0625;
            bad += want != eo[r * 40 + c];
            n += eo[r * 40 + c];
        }
    cr_expect_eq(bad, 0, "%d pixels break the half-open rule", bad);
    cr_expect_eq(n, 32 * 8, "%d object pixels, want 32 x 8", n);
    hv_slice_destroy(sl);
    hv_mesh_destroy(m);
}

Test(raster, wu_threshold_keeps_pixels_near_the_contour)
{
    double xy[16];
    for (int i = 0; i < 8; ++i) {
        xy[2 * i] = 5 + 3 * cos(2 * M_PI * i / 8);
        xy[2 * i + 1] = 5 + 3 * sin(2 * M_PI * i / 8);
    }
    hv_mesh *m = prism(xy, 8, 5, 5, 0, 1);
    hv_slice *sl = slice_mesh(m, 0.5);
    hv_raster_grid g = {90, 45, {0.5, 9.5}, {0.1, -0.2}};
    uint8_t *mask = malloc(90 * 45), *plain = malloc(90 * 45);
    cr_assert_eq(hv_slice_rasterize(sl, &g, HV_FILL_NONZERO, 0.35, mask, 0), HV_OK);
    cr_assert_eq(hv_slice_rasterize(sl, &g, HV_FILL_NONZERO, 0, plain, 0), HV_OK);
    int bad = 0, grown = 0;
    for (int r = 0; r < 45; ++r)
        for (int c = 0; c < 90; ++c) {
            double x = 0.5 + (c + 0.5) * 0.1, y = 9.5 - (r + 0.5) * 0.2, d = edge_distance(sl, x, y);
            if (fabs(d - 0.35) < 1e-9) continue;
            int want = plain[r * 90 + c] || d <= 0.35;
            bad += want != mask[r * 90 + c];
            grown += mask[r * 90 + c] && !plain[r * 90 + c];
        }
    cr_expect_eq(bad, 0);
    cr_expect(grown > 50, "the threshold added %d pixels", grown);
    free(mask);
    free(plain);
    hv_slice_destroy(sl);
    hv_mesh_destroy(m);
}

Test(raster, bad_arguments)
{
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_box(lo, hi, &m), HV_OK);
    hv_slice *sl = slice_mesh(m, 0.5);
    uint8_t mask[16];
    hv_raster_grid g = {4, 4, {0, 1}, {0.25, -0.25}};
    cr_expect_eq(hv_slice_rasterize(sl, &g, HV_FILL_NONZERO, -1, mask, 0), HV_ERR_INVALID);
    cr_expect_eq(hv_slice_rasterize(sl, &g, (hv_fill_rule)7, 0, mask, 0), HV_ERR_INVALID);
    cr_expect_eq(hv_slice_rasterize(sl, &g, HV_FILL_NONZERO, 0, mask, 2), HV_ERR_INVALID);
    g.pixel[0] = 0;
    cr_expect_eq(hv_slice_rasterize(sl, &g, HV_FILL_NONZERO, 0, mask, 0), HV_ERR_INVALID);
    g.pixel[0] = 0.25;
    cr_expect_eq(hv_slice_rasterize(sl, &g, HV_FILL_NONZERO, 0, mask, 0), HV_OK);
    int n = 0;
    for (int i = 0; i < 16; ++i) n += mask[i];
    cr_expect_eq(n, 16);
    hv_slice_destroy(sl);
    hv_mesh_destroy(m);
}
