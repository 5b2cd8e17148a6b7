/* tests/field/test_harmonic.c - hv_harmonic: linear profiles on bars (any axis, anisotropic
 * spacing, embedded in a larger grid), an L-shaped holed domain against a plain Gauss-Seidel
 * reference solve, floating components, the preconditioner's iteration count, thread-count
 * determinism, argument errors, non-convergence and cancel. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/core.h"
#include "hovox/field.h"

#define IDX(d, i, j, k) ((size_t)(((i) * (d)[1] + (j)) * (d)[2] + (k)))

typedef struct grid {
    int64_t d[3];
    size_t n;
    uint8_t *dom, *lab;
    float *phi;
} grid;

static grid grid_new(int64_t nx, int64_t ny, int64_t nz)
{
    grid g = {{nx, ny, nz}, (size_t)(nx * ny * nz), NULL, NULL, NULL};
    g.dom = calloc(g.n, 1);
    g.lab = calloc(g.n, 1);
    g.phi = malloc(g.n * sizeof(float));
    return g;
}

static void grid_free(grid *g)
{
    free(g->dom);
    free(g->lab);
    free(g->phi);
}

static const double iso[3] = {1, 1, 1};

/* A bar along `axis` filling the box [lo, hi) (inclusive-exclusive per axis), label 1 on its
 * first layer, label 2 on its last. The exact discrete solution is linear along the axis. */
static void make_bar(grid *g, int axis, const int64_t lo[3], const int64_t hi[3])
{
    for (int64_t i = lo[0]; i < hi[0]; ++i)
        for (int64_t j = lo[1]; j < hi[1]; ++j)
            for (int64_t k = lo[2]; k < hi[2]; ++k) {
                size_t v = IDX(g->d, i, j, k);
                int64_t p[3] = {i, j, k};
                g->dom[v] = 1;
                if (p[axis] == lo[axis]) g->lab[v] = 1;
                if (p[axis] == hi[axis] - 1) g->lab[v] = 2;
            }
}

/* phi must be 1 - t/(L-1) along the bar (t from its first layer), 0 outside it. The bound:
 * with tol 1e-10 the error is far below float rounding, so 2e-7 allows 3 ulps near 1. */
static void check_bar(const grid *g, int axis, const int64_t lo[3], const int64_t hi[3],
                      double bound)
{
    double worst = 0, asym = 0;
    for (int64_t i = 0; i < g->d[0]; ++i)
        for (int64_t j = 0; j < g->d[1]; ++j)
            for (int64_t k = 0; k < g->d[2]; ++k) {
                int64_t p[3] = {i, j, k};
                size_t v = IDX(g->d, i, j, k);
                int inside = 1;
                for (int a = 0; a < 3; ++a) inside &= p[a] >= lo[a] && p[a] < hi[a];
                if (!inside) {
                    cr_assert_eq(g->phi[v], 0.0f, "outside voxel (%lld,%lld,%lld) = %g",
                                 (long long)i, (long long)j, (long long)k, (double)g->phi[v]);
                    continue;
                }
                double len = (double)(hi[axis] - lo[axis] - 1);
                double t = (double)(p[axis] - lo[axis]);
                double e = fabs((double)g->phi[v] - (1.0 - t / len));
                if (e > worst) worst = e;
                /* symmetry: the mirrored voxel along the axis holds 1 - phi */
                int64_t m[3] = {i, j, k};
                m[axis] = lo[axis] + hi[axis] - 1 - p[axis];
                double s = fabs((double)g->phi[v] + (double)g->phi[IDX(g->d, m[0], m[1], m[2])] - 1);
                if (s > asym) asym = s;
            }
    cr_assert(worst <= bound, "bar along %c: max deviation from linear %.3g > %.3g", "xyz"[axis],
              worst, bound);
    cr_assert(asym <= 2 * bound, "bar along %c: asymmetry %.3g", "xyz"[axis], asym);
}

Test(harmonic, bar_is_linear_along_every_axis)
{
    for (int axis = 0; axis < 3; ++axis) {
        int64_t d[3] = {9, 10, 11};
        d[axis] = 33;
        grid g = grid_new(d[0], d[1], d[2]);
        int64_t lo[3] = {0, 0, 0};
        make_bar(&g, axis, lo, d);
        int it = -1;
        uint64_t fl = 99;
        cr_assert_eq(hv_harmonic(g.dom, g.lab, g.d, iso, 1e-10, 200, g.phi, &it, &fl, NULL), HV_OK,
                     "%s", hv_last_error());
        cr_assert_eq(fl, 0);
        cr_assert(it > 0 && it <= 30, "%d iterations", it);
        check_bar(&g, axis, lo, d, 2e-7);
        grid_free(&g);
    }
}

Test(harmonic, bar_with_anisotropic_spacing)
{
    static const double sp[][3] = {{0.5, 1.3, 2.0}, {2.0, 0.5, 1.3}, {1.3, 2.0, 0.5}};
    for (int c = 0; c < 3; ++c)
        for (int axis = 0; axis < 3; ++axis) {
            int64_t d[3] = {8, 7, 9};
            d[axis] = 30;
            grid g = grid_new(d[0], d[1], d[2]);
            int64_t lo[3] = {0, 0, 0};
            make_bar(&g, axis, lo, d);
            int it = 0;
            cr_assert_eq(hv_harmonic(g.dom, g.lab, g.d, sp[c], 1e-10, 300, g.phi, &it, NULL, NULL),
                         HV_OK, "%s", hv_last_error());
            check_bar(&g, axis, lo, d, 2e-7);
            grid_free(&g);
        }
}

/* The domain is a sub-box of a larger grid: zero flux across the domain boundary keeps the
 * profile linear, non-domain voxels get 0, labels outside the domain are ignored. */
Test(harmonic, embedded_bar_and_stray_labels)
{
    grid g = grid_new(20, 12, 40);
    int64_t lo[3] = {3, 2, 5}, hi[3] = {17, 9, 36};
    make_bar(&g, 2, lo, hi);
    g.lab[IDX(g.d, 0, 0, 0)] = 1; /* outside the domain: ignored */
    g.lab[IDX(g.d, 19, 11, 39)] = 2;
    g.lab[IDX(g.d, 10, 5, 20)] = 7; /* other label values: an ordinary domain voxel */
    const double sp[3] = {0.7, 1.1, 0.9};
    cr_assert_eq(hv_harmonic(g.dom, g.lab, g.d, sp, 1e-10, 300, g.phi, NULL, NULL, NULL), HV_OK,
                 "%s", hv_last_error());
    check_bar(&g, 2, lo, hi, 2e-7);
    grid_free(&g);
}

/* Gauss-Seidel (over-relaxed, for speed) on the same discrete problem written from scratch,
 * in double, iterated until the largest update is below 1e-14: the independent reference. */
static double *reference_solve(const grid *g, const double s[3])
{
    double *u = calloc(g->n, sizeof(double));
    const double w[3] = {1 / (s[0] * s[0]), 1 / (s[1] * s[1]), 1 / (s[2] * s[2])};
    for (size_t v = 0; v < g->n; ++v)
        if (g->dom[v] && g->lab[v] == 1) u[v] = 1;
    for (int sweep = 0; sweep < 200000; ++sweep) {
        double change = 0;
        for (int64_t i = 0; i < g->d[0]; ++i)
            for (int64_t j = 0; j < g->d[1]; ++j)
                for (int64_t k = 0; k < g->d[2]; ++k) {
                    size_t v = IDX(g->d, i, j, k);
                    if (!g->dom[v] || g->lab[v] == 1 || g->lab[v] == 2) continue;
                    double num = 0, den = 0;
                    int64_t p[3] = {i, j, k};
                    for (int a = 0; a < 3; ++a)
                        for (int sgn = -1; sgn <= 1; sgn += 2) {
                            int64_t q[3] = {p[0], p[1], p[2]};
                            q[a] += sgn;
                            if (q[a] < 0 || q[a] >= g->d[a]) continue;
                            size_t nb = IDX(g->d, q[0], q[1], q[2]);
                            if (!g->dom[nb]) continue;
                            num += w[a] * u[nb];
                            den += w[a];
                        }
                    double nv = u[v] + 1.8 * (num / den - u[v]); /* over-relaxed */
                    if (fabs(nv - u[v]) > change) change = fabs(nv - u[v]);
                    u[v] = nv;
                }
        if (change < 1e-14) return u;
    }
    cr_assert_fail("reference solve did not converge");
    return u;
}

/* An L-shaped plate with a hole, label 1 on the end of one arm, label 2 on the other. */
static grid make_l_holed(void)
{
    grid g = grid_new(22, 20, 5);
    for (int64_t i = 0; i < 22; ++i)
        for (int64_t j = 0; j < 20; ++j)
            for (int64_t k = 0; k < 5; ++k) {
                int in_l = (i < 8) || (j < 7);
                int hole = i >= 2 && i < 5 && j >= 3 && j < 5 && k >= 1 && k < 4;
                int notch = i >= 12 && i < 14 && j >= 2 && j < 7; /* a slot from the inner side */
                size_t v = IDX(g.d, i, j, k);
                g.dom[v] = (uint8_t)(in_l && !hole && !notch);
                if (g.dom[v] && j == 19) g.lab[v] = 1;
                if (g.dom[v] && i == 21) g.lab[v] = 2;
            }
    return g;
}

Test(harmonic, l_shaped_holed_domain_matches_gauss_seidel)
{
    static const double sp[][3] = {{1, 1, 1}, {0.8, 1.25, 0.6}};
    for (int c = 0; c < 2; ++c) {
        grid g = make_l_holed();
        int it = 0;
        uint64_t fl = 1;
        cr_assert_eq(hv_harmonic(g.dom, g.lab, g.d, sp[c], 1e-11, 300, g.phi, &it, &fl, NULL),
                     HV_OK, "%s", hv_last_error());
        cr_assert_eq(fl, 0);
        double *u = reference_solve(&g, sp[c]);
        double worst = 0;
        for (size_t v = 0; v < g.n; ++v) {
            double ref = g.dom[v] ? u[v] : 0.0;
            double e = fabs((double)g.phi[v] - ref);
            if (e > worst) worst = e;
            cr_assert(g.phi[v] >= 0.0f && g.phi[v] <= 1.0f);
        }
        cr_assert(worst <= 1e-6, "spacing %d: max difference from Gauss-Seidel %.3g", c, worst);
        free(u);
        grid_free(&g);
    }
}

Test(harmonic, floating_components)
{
    grid g = grid_new(30, 8, 8);
    /* the labelled bar: x in [0, 12) */
    int64_t lo[3] = {0, 0, 0}, hi[3] = {12, 8, 8};
    make_bar(&g, 0, lo, hi);
    /* a separate block with no label: x in [14, 20), 4x8x8 */
    for (int64_t i = 14; i < 20; ++i)
        for (int64_t j = 0; j < 8; ++j)
            for (int64_t k = 0; k < 8; ++k) g.dom[IDX(g.d, i, j, k)] = 1;
    /* a block touching only label 1: constant 1, not floating */
    for (int64_t i = 22; i < 30; ++i)
        for (int64_t j = 0; j < 4; ++j)
            for (int64_t k = 0; k < 4; ++k) {
                g.dom[IDX(g.d, i, j, k)] = 1;
                if (i == 29) g.lab[IDX(g.d, i, j, k)] = 1;
            }
    /* a single isolated voxel */
    g.dom[IDX(g.d, 25, 7, 7)] = 1;
    uint64_t fl = 0;
    cr_assert_eq(hv_harmonic(g.dom, g.lab, g.d, iso, 1e-10, 200, g.phi, NULL, &fl, NULL), HV_OK,
                 "%s", hv_last_error());
    cr_assert_eq(fl, 6 * 8 * 8 + 1, "floating %llu", (unsigned long long)fl);
    for (int64_t i = 14; i < 20; ++i)
        cr_assert_eq(g.phi[IDX(g.d, i, 3, 3)], 0.0f);
    cr_assert_eq(g.phi[IDX(g.d, 25, 7, 7)], 0.0f);
    for (int64_t i = 22; i < 30; ++i)
        cr_assert_float_eq(g.phi[IDX(g.d, i, 2, 1)], 1.0, 1e-6, "x=%lld", (long long)i);
    for (int64_t i = 0; i < 12; ++i) /* the labelled bar is unaffected by the others */
        cr_assert_float_eq(g.phi[IDX(g.d, i, 5, 2)], 1.0 - (double)i / 11.0, 2e-7, "x=%lld",
                           (long long)i);
    grid_free(&g);
}

/* Multigrid makes the iteration count nearly independent of the size; plain or Jacobi CG
 * needs O(n) iterations (over 100 here). */
Test(harmonic, preconditioner_keeps_iterations_low)
{
    int prev = 0;
    for (int64_t n = 16; n <= 64; n *= 2) {
        grid g = grid_new(n, n, n);
        for (int64_t i = 0; i < n; ++i)
            for (int64_t j = 0; j < n; ++j)
                for (int64_t k = 0; k < n; ++k) {
                    double x = (double)i - (n - 1) / 2.0, y = (double)j - (n - 1) / 2.0,
                           z = (double)k - (n - 1) / 2.0, r = 0.45 * (double)n;
                    size_t v = IDX(g.d, i, j, k);
                    if (x * x + y * y + z * z > r * r) continue;
                    g.dom[v] = 1;
                    if (x < -0.8 * r) g.lab[v] = 1;
                    if (x > 0.8 * r) g.lab[v] = 2;
                }
        int it = 0;
        cr_assert_eq(hv_harmonic(g.dom, g.lab, g.d, iso, 1e-8, 100, g.phi, &it, NULL, NULL), HV_OK,
                     "%s", hv_last_error());
        cr_assert(it <= 20, "sphere %lld^3: %d iterations", (long long)n, it);
        cr_assert(prev == 0 || it <= prev + 4, "sphere %lld^3: %d iterations (was %d)",
                  (long long)n, it, prev);
        prev = it;
        grid_free(&g);
    }
}

Test(harmonic, identical_bytes_for_any_thread_count)
{
    grid g = make_l_holed();
    grid big = grid_new(40, 30, 24); /* above the serial threshold */
    for (size_t v = 0; v < big.n; ++v) big.dom[v] = (uint8_t)((v * 2654435761u >> 7) % 11 != 0);
    for (int64_t j = 0; j < 30; ++j)
        for (int64_t k = 0; k < 24; ++k) {
            big.dom[IDX(big.d, 0, j, k)] = big.dom[IDX(big.d, 39, j, k)] = 1;
            big.lab[IDX(big.d, 0, j, k)] = 1;
            big.lab[IDX(big.d, 39, j, k)] = 2;
        }
    float *ref = NULL, *refbig = NULL;
    static const int threads[] = {1, 2, 5};
    for (int t = 0; t < 3; ++t) {
        hv_set_threads(threads[t]);
        int it1 = 0, it2 = 0;
        cr_assert_eq(hv_harmonic(g.dom, g.lab, g.d, iso, 1e-9, 200, g.phi, &it1, NULL, NULL),
                     HV_OK, "%s", hv_last_error());
        const double sp[3] = {1, 0.9, 1.2};
        cr_assert_eq(hv_harmonic(big.dom, big.lab, big.d, sp, 1e-9, 200, big.phi, &it2, NULL, NULL),
                     HV_OK, "%s", hv_last_error());
        if (!ref) {
            ref = malloc(g.n * sizeof(float));
            refbig = malloc(big.n * sizeof(float));
            memcpy(ref, g.phi, g.n * sizeof(float));
            memcpy(refbig, big.phi, big.n * sizeof(float));
        } else {
            cr_assert(memcmp(ref, g.phi, g.n * sizeof(float)) == 0, "%d threads differ",
                      threads[t]);
            cr_assert(memcmp(refbig, big.phi, big.n * sizeof(float)) == 0, "%d threads differ",
                      threads[t]);
        }
    }
    hv_set_threads(0);
    free(ref);
    free(refbig);
    grid_free(&g);
    grid_free(&big);
}

Test(harmonic, line_and_single_voxel_grids)
{
    grid g = grid_new(1, 17, 1);
    int64_t lo[3] = {0, 0, 0};
    make_bar(&g, 1, lo, g.d);
    cr_assert_eq(hv_harmonic(g.dom, g.lab, g.d, iso, 1e-10, 100, g.phi, NULL, NULL, NULL), HV_OK,
                 "%s", hv_last_error());
    check_bar(&g, 1, lo, g.d, 2e-7);
    grid_free(&g);
    /* everything labelled: nothing to solve */
    grid h = grid_new(2, 1, 1);
    h.dom[0] = h.dom[1] = 1;
    h.lab[0] = 1;
    h.lab[1] = 2;
    int it = 5;
    cr_assert_eq(hv_harmonic(h.dom, h.lab, h.d, iso, 1e-6, 10, h.phi, &it, NULL, NULL), HV_OK);
    cr_assert_eq(it, 0);
    cr_assert_eq(h.phi[0], 1.0f);
    cr_assert_eq(h.phi[1], 0.0f);
    grid_free(&h);
}

static void expect_err(hv_status want, const grid *g, const int64_t d[3], const double s[3],
                       double tol, int max_iter, const char *needle)
{
    hv_status got = hv_harmonic(g->dom, g->lab, d, s, tol, max_iter, g->phi, NULL, NULL, NULL);
    cr_assert_eq(got, want, "%s: got %s (%s)", needle, hv_status_name(got), hv_last_error());
    cr_assert(strstr(hv_last_error(), needle) != NULL, "message '%s' lacks '%s'", hv_last_error(),
              needle);
}

Test(harmonic, invalid_arguments)
{
    grid g = grid_new(10, 4, 4);
    int64_t lo[3] = {0, 0, 0};
    make_bar(&g, 0, lo, g.d);
    cr_assert_eq(hv_harmonic(NULL, g.lab, g.d, iso, 1e-6, 10, g.phi, NULL, NULL, NULL),
                 HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "domain is NULL"), "%s", hv_last_error());
    cr_assert_eq(hv_harmonic(g.dom, g.lab, g.d, iso, 1e-6, 10, NULL, NULL, NULL, NULL),
                 HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "phi is NULL"), "%s", hv_last_error());
    int64_t bad[3] = {10, 0, 4}, neg[3] = {10, 4, -1};
    expect_err(HV_ERR_INVALID, &g, bad, iso, 1e-6, 10, "dimension y must be >= 1 (got 0)");
    expect_err(HV_ERR_INVALID, &g, neg, iso, 1e-6, 10, "dimension z must be >= 1 (got -1)");
    const double s0[3] = {1, 0, 1}, sn[3] = {NAN, 1, 1};
    expect_err(HV_ERR_INVALID, &g, g.d, s0, 1e-6, 10, "spacing y must be finite and > 0 (got 0)");
    expect_err(HV_ERR_INVALID, &g, g.d, sn, 1e-6, 10, "spacing x must be finite and > 0");
    const double stiny[3] = {1, 1, 1e-25}, sbig[3] = {1e25, 1, 1};
    expect_err(HV_ERR_INVALID, &g, g.d, stiny, 1e-6, 10,
               "spacing z out of range for float weights (got 1e-25)");
    expect_err(HV_ERR_INVALID, &g, g.d, sbig, 1e-6, 10, "spacing x out of range");
    expect_err(HV_ERR_INVALID, &g, g.d, iso, 0, 10, "tolerance must be in (0, 1) (got 0)");
    expect_err(HV_ERR_INVALID, &g, g.d, iso, 1.5, 10, "tolerance must be in (0, 1) (got 1.5)");
    expect_err(HV_ERR_INVALID, &g, g.d, iso, NAN, 10, "tolerance must be in (0, 1)");
    expect_err(HV_ERR_INVALID, &g, g.d, iso, 1e-6, 0, "max_iter must be >= 1 (got 0)");
    int64_t huge[3] = {(int64_t)1 << 30, (int64_t)1 << 30, 2};
    expect_err(HV_ERR_LIMIT, &g, huge, iso, 1e-6, 10, "exceed the limit of 2^40");
    grid_free(&g);
}

Test(harmonic, missing_labels)
{
    grid g = grid_new(10, 4, 4);
    int64_t lo[3] = {0, 0, 0};
    make_bar(&g, 0, lo, g.d);
    for (size_t v = 0; v < g.n; ++v)
        if (g.lab[v] == 2) g.lab[v] = 0;
    expect_err(HV_ERR_INVALID, &g, g.d, iso, 1e-6, 10, "no domain voxel is labelled 2");
    for (size_t v = 0; v < g.n; ++v) g.lab[v] = g.lab[v] == 1 ? 2 : 0;
    expect_err(HV_ERR_INVALID, &g, g.d, iso, 1e-6, 10, "no domain voxel is labelled 1");
    /* label 1 present but only outside the domain */
    for (size_t v = 0; v < g.n; ++v)
        if (g.lab[v] == 0 && v % 7 == 0) {
            g.lab[v] = 1;
            g.dom[v] = 0;
        }
    expect_err(HV_ERR_INVALID, &g, g.d, iso, 1e-6, 10, "no domain voxel is labelled 1");
    grid_free(&g);
}

Test(harmonic, no_convergence_reports_the_residual)
{
    grid g = make_l_holed();
    int it = 0;
    hv_status s = hv_harmonic(g.dom, g.lab, g.d, iso, 1e-12, 2, g.phi, &it, NULL, NULL);
    cr_assert_eq(s, HV_ERR_LIMIT, "%s", hv_status_name(s));
    cr_assert_eq(it, 2);
    cr_assert(strstr(hv_last_error(), "no convergence in 2 iterations (relative residual"),
              "%s", hv_last_error());
    grid_free(&g);
}

static int cancel_after(void *user, const char *stage, double fraction)
{
    (void)fraction;
    cr_assert(strncmp(stage, "harmonic", 8) == 0, "stage '%s'", stage);
    return --*(int *)user < 0;
}

Test(harmonic, progress_and_cancel)
{
    grid g = make_l_holed();
    int budget = 1000;
    hv_progress p = {cancel_after, &budget};
    cr_assert_eq(hv_harmonic(g.dom, g.lab, g.d, iso, 1e-10, 100, g.phi, NULL, NULL, &p), HV_OK,
                 "%s", hv_last_error());
    cr_assert(budget < 1000 - 2, "progress called %d times", 1000 - budget);
    budget = 2; /* setup, one iteration, then cancel */
    cr_assert_eq(hv_harmonic(g.dom, g.lab, g.d, iso, 1e-10, 100, g.phi, NULL, NULL, &p),
                 HV_ERR_CANCELLED);
    cr_assert(strstr(hv_last_error(), "cancelled"), "%s", hv_last_error());
    grid_free(&g);
}
