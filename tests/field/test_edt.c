/* tests/field/test_edt.c - hv_edt against a brute-force nearest-feature search (random masks
 * of several sizes, densities and spacings, degenerate grids), analytic single-feature
 * distances, no feature (INFINITY), thread-count determinism, argument errors, cancel. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/core.h"
#include "hovox/field.h"
#include "field/field_internal.h"

/* Deterministic xorshift so every run tests the same masks. */
static uint64_t rng_state;
static uint64_t rng(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}
static double rng_unit(void) { return (double)(rng() >> 11) * (1.0 / 9007199254740992.0); }

static uint8_t *random_mask(const int64_t d[3], double density, uint64_t seed)
{
    size_t n = (size_t)(d[0] * d[1] * d[2]);
    uint8_t *m = malloc(n);
    rng_state = seed * 0x9E3779B97F4A7C15ull + 1;
    for (size_t v = 0; v < n; ++v) m[v] = rng_unit() < density ? (uint8_t)(1 + rng() % 255) : 0;
    return m;
}

/* O(N * F) reference: the exact squared distance in double, then sqrt. */
static double *brute(const uint8_t *m, const int64_t d[3], const double s[3])
{
    size_t n = (size_t)(d[0] * d[1] * d[2]), nf = 0;
    int64_t(*feat)[3] = malloc((n + 1) * sizeof *feat);
    for (int64_t i = 0; i < d[0]; ++i)
        for (int64_t j = 0; j < d[1]; ++j)
            for (int64_t k = 0; k < d[2]; ++k)
                if (m[(i * d[1] + j) * d[2] + k]) {
                    feat[nf][0] = i;
                    feat[nf][1] = j;
                    feat[nf][2] = k;
                    ++nf;
                }
    double *r = malloc(n * sizeof *r);
    for (int64_t i = 0; i < d[0]; ++i)
        for (int64_t j = 0; j < d[1]; ++j)
            for (int64_t k = 0; k < d[2]; ++k) {
                double best = INFINITY;
                for (size_t f = 0; f < nf; ++f) {
                    double dx = (double)(i - feat[f][0]) * s[0], dy = (double)(j - feat[f][1]) * s[1],
                           dz = (double)(k - feat[f][2]) * s[2];
                    double d2 = dx * dx + dy * dy + dz * dz;
                    if (d2 < best) best = d2;
                }
                r[(i * d[1] + j) * d[2] + k] = sqrt(best);
            }
    free(feat);
    return r;
}

/* Exact within float rounding of the exact value (relative 2e-7: squared distances are
 * stored as float between passes), exact 0 on features and INFINITY without features. */
static void check_against_brute(const uint8_t *m, const int64_t d[3], const double s[3],
                                const char *what)
{
    size_t n = (size_t)(d[0] * d[1] * d[2]);
    float *out = malloc(n * sizeof *out);
    cr_assert_eq(hv_edt(m, d, s, out, NULL), HV_OK, "%s: %s", what, hv_last_error());
    double *ref = brute(m, d, s);
    for (size_t v = 0; v < n; ++v) {
        if (isinf(ref[v])) {
            cr_assert(isinf(out[v]) && out[v] > 0, "%s: voxel %zu: %g, expected inf", what, v,
                      (double)out[v]);
        } else if (ref[v] == 0) {
            cr_assert_eq(out[v], 0.0f, "%s: voxel %zu is a feature but got %g", what, v,
                         (double)out[v]);
        } else {
            cr_assert(fabs((double)out[v] - ref[v]) <= 2e-7 * ref[v],
                      "%s: voxel %zu (%lld,%lld,%lld): %.9g, expected %.9g", what, v,
                      (long long)(v / (size_t)(d[1] * d[2])),
                      (long long)(v / (size_t)d[2] % (size_t)d[1]), (long long)(v % (size_t)d[2]),
                      (double)out[v], ref[v]);
        }
    }
    free(ref);
    free(out);
}

static void random_case(int64_t nx, int64_t ny, int64_t nz, double density, const double s[3],
                        uint64_t seed)
{
    int64_t d[3] = {nx, ny, nz};
    uint8_t *m = random_mask(d, density, seed);
    char what[128];
    snprintf(what, sizeof what, "%lldx%lldx%lld density %g spacing (%g,%g,%g)", (long long)nx,
             (long long)ny, (long long)nz, density, s[0], s[1], s[2]);
    check_against_brute(m, d, s, what);
    free(m);
}

static const double iso[3] = {1, 1, 1};
static const double aniso[3] = {0.5, 1.3, 2.0};
static const double aniso2[3] = {2.0, 0.5, 1.3};

Test(edt, random_masks_match_brute_force)
{
    static const double density[] = {0.001, 0.05, 0.5};
    for (int t = 0; t < 2; ++t) {
        hv_set_threads(t ? 2 : 1);
        for (size_t i = 0; i < sizeof density / sizeof density[0]; ++i) {
            random_case(23, 17, 31, density[i], iso, 1 + i);
            random_case(23, 17, 31, density[i], aniso, 11 + i);
            random_case(23, 17, 31, density[i], aniso2, 21 + i);
        }
    }
    hv_set_threads(0);
}

/* Rows longer than one tile of columns, widths that leave partial tiles, few slices (the
 * unfused z/y path) and many. */
Test(edt, tiles_and_paths)
{
    hv_set_threads(2);
    random_case(9, 21, 70, 0.02, iso, 31);
    random_case(9, 21, 70, 0.3, aniso, 32);
    random_case(3, 37, 65, 0.01, aniso2, 33);
    random_case(40, 6, 33, 0.003, aniso, 34);
    random_case(2, 2, 129, 0.05, iso, 35);
    random_case(48, 40, 97, 0.0005, aniso2, 36); /* several full tiles, long distances */
    random_case(1, 1, 3000, 0.001, aniso, 37);
    hv_set_threads(0);
}

Test(edt, degenerate_dims)
{
    static const int64_t dims[][3] = {{1, 1, 1}, {1, 40, 1}, {40, 1, 1}, {1, 1, 40},
                                      {1, 13, 9}, {11, 1, 7}, {6, 8, 1}, {1, 1, 200}};
    for (size_t c = 0; c < sizeof dims / sizeof dims[0]; ++c)
        for (int dens = 0; dens < 3; ++dens) {
            double density = dens == 0 ? 0.02 : dens == 1 ? 0.2 : 0.9;
            random_case(dims[c][0], dims[c][1], dims[c][2], density, aniso, 40 + c * 3 + dens);
            random_case(dims[c][0], dims[c][1], dims[c][2], density, iso, 90 + c * 3 + dens);
        }
}

Test(edt, single_feature_is_analytic)
{
    int64_t d[3] = {19, 14, 45};
    const double s[3] = {0.7, 1.9, 0.35};
    size_t n = 19 * 14 * 45;
    uint8_t *m = calloc(n, 1);
    const int64_t f[3] = {4, 13, 17};
    m[(f[0] * d[1] + f[1]) * d[2] + f[2]] = 1;
    float *out = malloc(n * sizeof *out);
    cr_assert_eq(hv_edt(m, d, s, out, NULL), HV_OK, "%s", hv_last_error());
    for (int64_t i = 0; i < d[0]; ++i)
        for (int64_t j = 0; j < d[1]; ++j)
            for (int64_t k = 0; k < d[2]; ++k) {
                double e = hypot(hypot((double)(i - f[0]) * s[0], (double)(j - f[1]) * s[1]),
                                 (double)(k - f[2]) * s[2]);
                double got = out[(i * d[1] + j) * d[2] + k];
                cr_assert(fabs(got - e) <= 2e-7 * e, "(%lld,%lld,%lld): %.9g vs %.9g",
                          (long long)i, (long long)j, (long long)k, got, e);
            }
    free(m);
    free(out);
}

Test(edt, no_feature_gives_infinity)
{
    int64_t d[3] = {5, 33, 40};
    size_t n = 5 * 33 * 40;
    uint8_t *m = calloc(n, 1);
    float *out = malloc(n * sizeof *out);
    cr_assert_eq(hv_edt(m, d, iso, out, NULL), HV_OK, "%s", hv_last_error());
    for (size_t v = 0; v < n; ++v) cr_assert(isinf(out[v]) && out[v] > 0, "voxel %zu", v);
    free(m);
    free(out);
}

/* Features only in one x-slice: every y and x row elsewhere starts as all INFINITY. */
Test(edt, feature_plane_gives_plane_distance)
{
    int64_t d[3] = {12, 9, 35};
    const double s[3] = {1.5, 1, 1};
    size_t n = 12 * 9 * 35;
    uint8_t *m = calloc(n, 1);
    memset(m + (size_t)(7 * 9 * 35), 1, 9 * 35);
    float *out = malloc(n * sizeof *out);
    cr_assert_eq(hv_edt(m, d, s, out, NULL), HV_OK, "%s", hv_last_error());
    for (int64_t i = 0; i < d[0]; ++i)
        for (size_t v = 0; v < 9 * 35; ++v)
            cr_assert_float_eq(out[(size_t)i * 9 * 35 + v], fabs((double)(i - 7)) * 1.5, 1e-6);
    free(m);
    free(out);
}

Test(edt, identical_bytes_for_any_thread_count)
{
    int64_t d[3] = {41, 37, 75};
    size_t n = 41 * 37 * 75;
    uint8_t *m = random_mask(d, 0.01, 77);
    float *out[3];
    static const int threads[3] = {1, 2, 5};
    for (int t = 0; t < 3; ++t) {
        hv_set_threads(threads[t]);
        out[t] = malloc(n * sizeof(float));
        cr_assert_eq(hv_edt(m, d, aniso, out[t], NULL), HV_OK, "%s", hv_last_error());
    }
    hv_set_threads(0);
    cr_assert(memcmp(out[0], out[1], n * sizeof(float)) == 0, "1 vs 2 threads differ");
    cr_assert(memcmp(out[0], out[2], n * sizeof(float)) == 0, "1 vs 5 threads differ");
    /* and the few-slices path */
    int64_t d2[3] = {3, 50, 70};
    uint8_t *m2 = random_mask(d2, 0.02, 78);
    float *a = malloc(3 * 50 * 70 * sizeof(float)), *b = malloc(3 * 50 * 70 * sizeof(float));
    hv_set_threads(1);
    cr_assert_eq(hv_edt(m2, d2, aniso, a, NULL), HV_OK);
    hv_set_threads(5);
    cr_assert_eq(hv_edt(m2, d2, aniso, b, NULL), HV_OK);
    hv_set_threads(0);
    cr_assert(memcmp(a, b, 3 * 50 * 70 * sizeof(float)) == 0);
    for (int t = 0; t < 3; ++t) free(out[t]);
    free(a);
    free(b);
    free(m);
    free(m2);
}

static void expect_invalid(const uint8_t *m, const int64_t d[3], const double s[3], float *out,
                           const char *needle)
{
    cr_assert_eq(hv_edt(m, d, s, out, NULL), HV_ERR_INVALID, "expected HV_ERR_INVALID (%s)",
                 needle);
    cr_assert(strstr(hv_last_error(), needle) != NULL, "message '%s' lacks '%s'", hv_last_error(),
              needle);
}

Test(edt, invalid_arguments)
{
    uint8_t m[8] = {1};
    float out[8];
    int64_t d[3] = {2, 2, 2};
    expect_invalid(NULL, d, iso, out, "feature is NULL");
    expect_invalid(m, NULL, iso, out, "dims is NULL");
    expect_invalid(m, d, NULL, out, "spacing is NULL");
    expect_invalid(m, d, iso, NULL, "out is NULL");
    int64_t bad[3] = {2, 0, 2};
    expect_invalid(m, bad, iso, out, "dimension y must be >= 1 (got 0)");
    int64_t neg[3] = {-3, 2, 2};
    expect_invalid(m, neg, iso, out, "dimension x must be >= 1 (got -3)");
    double s0[3] = {1, 1, 0}, sn[3] = {NAN, 1, 1}, si[3] = {1, INFINITY, 1}, sneg[3] = {1, -1, 1};
    expect_invalid(m, d, s0, out, "spacing z must be finite and > 0 (got 0)");
    expect_invalid(m, d, sn, out, "spacing x must be finite and > 0 (got nan)");
    expect_invalid(m, d, si, out, "spacing y must be finite and > 0 (got inf)");
    expect_invalid(m, d, sneg, out, "spacing y must be finite and > 0 (got -1)");
    double tiny[3] = {1, 1e-20, 1}, big[3] = {1e19, 1, 1};
    expect_invalid(m, d, tiny, out, "spacing y too small for float squared distances (got 1e-20)");
    expect_invalid(m, d, big, out, "grid too large in physical units");
    /* too many voxels: refused before anything is touched or allocated */
    int64_t huge[3] = {(int64_t)1 << 21, (int64_t)1 << 20, 2};
    cr_assert_eq(hv_edt(m, huge, iso, out, NULL), HV_ERR_LIMIT);
    cr_assert(strstr(hv_last_error(), "exceed the limit of 2^40") != NULL, "%s", hv_last_error());
    int64_t wrap[3] = {(int64_t)1 << 40, (int64_t)1 << 40, (int64_t)1 << 40};
    cr_assert_eq(hv_edt(m, wrap, iso, out, NULL), HV_ERR_LIMIT);
}

static int cancel_at_first(void *user, const char *stage, double fraction)
{
    (void)stage;
    (void)fraction;
    ++*(int *)user;
    return 1;
}

static int count_calls(void *user, const char *stage, double fraction)
{
    cr_assert(strncmp(stage, "edt", 3) == 0, "stage '%s'", stage);
    cr_assert(fraction >= 0 && fraction <= 1);
    ++*(int *)user;
    return 0;
}

Test(edt, progress_and_cancel)
{
    int64_t d[3] = {30, 20, 40};
    uint8_t *m = random_mask(d, 0.01, 5);
    float *out = malloc(30 * 20 * 40 * sizeof(float));
    int calls = 0;
    hv_progress p = {count_calls, &calls};
    cr_assert_eq(hv_edt(m, d, iso, out, &p), HV_OK, "%s", hv_last_error());
    cr_assert_geq(calls, 2);
    calls = 0;
    hv_progress c = {cancel_at_first, &calls};
    cr_assert_eq(hv_edt(m, d, iso, out, &c), HV_ERR_CANCELLED);
    cr_assert_eq(calls, 1, "the callback ran %d times after cancelling", calls);
    cr_assert(strstr(hv_last_error(), "cancelled") != NULL, "%s", hv_last_error());
    free(m);
    free(out);
}

/* hv_edt_less (the contour's depth, offset in the EDT's last pass) is max(hv_edt - less, 0) to the
 * bit, on a random mask with a width that is no multiple of the 4-wide transpose; a negative or
 * non-finite offset is refused. */
Test(edt, less_is_the_clamped_difference)
{
    int64_t d[3] = {23, 17, 31};
    const double s[3] = {0.5, 0.5, 0.75};
    size_t n = 23 * 17 * 31;
    uint8_t *m = malloc(n);
    uint64_t r = 99;
    for (size_t v = 0; v < n; ++v) {
        r = r * 6364136223846793005ull + 1442695040888963407ull;
        m[v] = (r >> 60) < 3;
    }
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    cr_assert_eq(hv_edt(m, d, s, a, NULL), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_edt_less(m, d, s, 0.6f, b, NULL), HV_OK, "%s", hv_last_error());
    size_t clamped = 0;
    for (size_t v = 0; v < n; ++v) {
        float want = fmaxf(a[v] - 0.6f, 0.0f);
        cr_assert(b[v] == want, "voxel %zu: %.9g, want %.9g", v, b[v], want);
        clamped += a[v] > 0 && want == 0;
    }
    cr_expect_gt(clamped, 0, "no distance below the offset: the clamp went untested");
    cr_assert_eq(hv_edt_less(m, d, s, -1.0f, b, NULL), HV_ERR_INVALID);
    cr_assert_eq(hv_edt_less(m, d, s, NAN, b, NULL), HV_ERR_INVALID);
    free(m);
    free(a);
    free(b);
}
