/* tests/slicing/test_poi.c - pixel overlap interpolation (Wu 2.4.2): Wu's 5x5 -> 3x3 and
 * 2x2 -> 3x3 coefficients, a brute-force rectangle-overlap reference, mass conservation for
 * random images and ratios, composition, and the repeated (stepwise) resampling. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "slicing/layers_internal.h"
#include "hovox/layers.h"

static uint64_t g_rng = 88172645463325252ull;
static double urand(void)
{
    g_rng ^= g_rng << 13;
    g_rng ^= g_rng >> 7;
    g_rng ^= g_rng << 17;
    return (double)(g_rng >> 11) * (1.0 / 9007199254740992.0);
}

/* Weight of old pixel (ox, oy) in new pixel (nx, ny) of an sw x sh -> dw x dh membrane
 * resample, read from the operator by resampling a unit impulse. */
static void impulse(int sw, int sh, int dw, int dh, int ox, int oy, float *dst)
{
    float *src = calloc((size_t)sw * sh, sizeof *src);
    src[oy * sw + ox] = 1;
    cr_assert_eq(hv_poi_resample(src, sw, sh, dst, dw, dh), HV_OK, "%s", hv_last_error());
    free(src);
}

/* The axis weights, in double, as Wu writes them: 5 -> 3 along one axis is 0.6/0.4 and
 * 0.2/0.6/0.2; the 2-D coefficient is the product. */
static double axis_weight(const hv_poi_axis *a, int out, int in)
{
    if (in < a->start[out] || in >= a->start[out] + a->len[out]) return 0;
    return a->w[a->off[out] + (size_t)(in - a->start[out])];
}

Test(poi, wu_5x5_to_3x3_exact)
{
    hv_poi_axis a;
    /* the membrane in integer units: old pixels 3 wide, new pixels 5 wide */
    cr_assert_eq(hv_poi_axis_step(0, 3, 5, 0, 5, 3, &a), HV_OK);
    /* N1 = 0.36 O1 + 0.24 (O2 + O6) + 0.16 O7 (O numbered row by row from 1) */
    double n1[25] = {0};
    n1[0] = 0.36;
    n1[1] = n1[5] = 0.24;
    n1[6] = 0.16;
    /* N2 = 0.12 (O2 + O4) + 0.36 O3 + 0.08 (O7 + O9) + 0.24 O8 */
    double n2[25] = {0};
    n2[1] = n2[3] = 0.12;
    n2[2] = 0.36;
    n2[6] = n2[8] = 0.08;
    n2[7] = 0.24;
    for (int o = 0; o < 25; ++o) {
        int ox = o % 5, oy = o / 5;
        double w1 = axis_weight(&a, 0, ox) * axis_weight(&a, 0, oy);
        double w2 = axis_weight(&a, 1, ox) * axis_weight(&a, 0, oy);
        cr_expect(fabs(w1 - n1[o]) < 1e-15, "N1 weight of O%d: %.17g, Wu %.2f", o + 1, w1, n1[o]);
        cr_expect(fabs(w2 - n2[o]) < 1e-15, "N2 weight of O%d: %.17g, Wu %.2f", o + 1, w2, n2[o]);
    }
    hv_poi_axis_free(&a);
    /* and through the public float API, within float rounding */
    float dst[9];
    for (int o = 0; o < 25; ++o) {
        impulse(5, 5, 3, 3, o % 5, o / 5, dst);
        cr_expect(fabsf(dst[0] - (float)n1[o]) < 1e-7f, "N1 <- O%d: %.9g", o + 1, dst[0]);
        cr_expect(fabsf(dst[1] - (float)n2[o]) < 1e-7f, "N2 <- O%d: %.9g", o + 1, dst[1]);
    }
}

Test(poi, wu_2x2_to_3x3_exact)
{
    /* N1 = O1, N3 = O2, N7 = O3, N9 = O4, N2 = 0.5 (O1 + O2), N4 = 0.5 (O1 + O3),
     * N6 = 0.5 (O2 + O4), N8 = 0.5 (O3 + O4), N5 = 0.25 (O1 + O2 + O3 + O4) */
    static const double want[9][4] = {
        {1, 0, 0, 0},   {0.5, 0.5, 0, 0},        {0, 1, 0, 0},
        {0.5, 0, 0.5, 0}, {0.25, 0.25, 0.25, 0.25}, {0, 0.5, 0, 0.5},
        {0, 0, 1, 0},   {0, 0, 0.5, 0.5},        {0, 0, 0, 1}};
    float dst[9];
    for (int o = 0; o < 4; ++o) {
        impulse(2, 2, 3, 3, o % 2, o / 2, dst);
        for (int n = 0; n < 9; ++n)
            cr_expect(dst[n] == (float)want[n][o], "N%d <- O%d: %.9g, Wu %.2f", n + 1, o + 1, dst[n], want[n][o]);
    }
}

/* Independent reference: every pair of rectangles intersected in 2-D. */
static void brute(const float *src, int sw, int sh, double *dst, int dw, int dh)
{
    double W = 1.0, H = 1.0; /* both images cover the unit square */
    for (int y = 0; y < dh; ++y)
        for (int x = 0; x < dw; ++x) {
            double ax0 = x * W / dw, ax1 = (x + 1) * W / dw, ay0 = y * H / dh, ay1 = (y + 1) * H / dh;
            double acc = 0, area = 0;
            for (int j = 0; j < sh; ++j)
                for (int i = 0; i < sw; ++i) {
                    double bx0 = i * W / sw, bx1 = (i + 1) * W / sw, by0 = j * H / sh, by1 = (j + 1) * H / sh;
                    double ox = fmin(ax1, bx1) - fmax(ax0, bx0), oy = fmin(ay1, by1) - fmax(ay0, by0);
                    if (ox <= 0 || oy <= 0) continue;
                    acc += ox * oy * src[j * sw + i];
                    area += ox * oy;
                }
            dst[y * dw + x] = acc / area;
        }
}

Test(poi, matches_brute_force_overlap)
{
    for (int t = 0; t < 40; ++t) {
        int sw = 1 + (int)(urand() * 17), sh = 1 + (int)(urand() * 17);
        int dw = 1 + (int)(urand() * 23), dh = 1 + (int)(urand() * 23);
        float *src = malloc(sizeof(float) * sw * sh), *dst = malloc(sizeof(float) * dw * dh);
        double *ref = malloc(sizeof(double) * dw * dh);
        for (int i = 0; i < sw * sh; ++i) src[i] = (float)urand();
        cr_assert_eq(hv_poi_resample(src, sw, sh, dst, dw, dh), HV_OK);
        brute(src, sw, sh, ref, dw, dh);
        for (int i = 0; i < dw * dh; ++i)
            cr_assert(fabs(dst[i] - ref[i]) < 1e-6, "%dx%d -> %dx%d pixel %d: %.9g vs %.9g", sw, sh, dw, dh, i, dst[i],
                      ref[i]);
        free(src);
        free(dst);
        free(ref);
    }
}

/* sum(value x pixel area) over the common rectangle is the same before and after */
static double mass(const float *img, int w, int h)
{
    double s = 0;
    for (int i = 0; i < w * h; ++i) s += img[i];
    return s / ((double)w * h);
}

Test(poi, mass_conservation_random)
{
    for (int t = 0; t < 200; ++t) {
        int sw = 1 + (int)(urand() * 60), sh = 1 + (int)(urand() * 60);
        int dw = 1 + (int)(urand() * 300), dh = 1 + (int)(urand() * 300);
        double ratio = urand() < 0.3 ? 1.0 : 1.05 + urand() * 3; /* 1: one exact step */
        float *src = malloc(sizeof(float) * sw * sh), *dst = malloc(sizeof(float) * dw * dh);
        for (int i = 0; i < sw * sh; ++i) src[i] = (float)urand();
        cr_assert_eq(hv_poi_resample_steps(src, sw, sh, dst, dw, dh, ratio), HV_OK, "%s", hv_last_error());
        double a = mass(src, sw, sh), b = mass(dst, dw, dh);
        cr_assert(fabs(a - b) <= 1e-6 * fabs(a), "%dx%d -> %dx%d (step %.3f): mass %.12g -> %.12g", sw, sh, dw, dh,
                  ratio, a, b);
        free(src);
        free(dst);
    }
}

Test(poi, constant_stays_constant_and_fractions_sum_to_one)
{
    /* three fraction images summing to 1 stay summing to 1 after any resampling */
    int sw = 13, sh = 9, dw = 97, dh = 41;
    float *f[3], *g[3];
    for (int k = 0; k < 3; ++k) {
        f[k] = malloc(sizeof(float) * sw * sh);
        g[k] = malloc(sizeof(float) * dw * dh);
    }
    for (int i = 0; i < sw * sh; ++i) {
        double a = urand(), b = urand() * (1 - a);
        f[0][i] = (float)a;
        f[1][i] = (float)b;
        f[2][i] = (float)(1 - a - b);
    }
    for (int k = 0; k < 3; ++k) cr_assert_eq(hv_poi_resample_steps(f[k], sw, sh, g[k], dw, dh, 1.5), HV_OK);
    for (int i = 0; i < dw * dh; ++i) cr_assert(fabs(g[0][i] + g[1][i] + g[2][i] - 1) < 1e-6);
    for (int k = 0; k < 3; ++k) {
        free(f[k]);
        free(g[k]);
    }
}

Test(poi, compose_equals_matrix_product)
{
    hv_poi_axis a, b, c;
    cr_assert_eq(hv_poi_axis_step(0.3, 0.7, 11, 0.1, 0.45, 17, &a), HV_OK);
    cr_assert_eq(hv_poi_axis_step(0.1, 0.45, 17, 7.9, -0.31, 23, &b), HV_OK);
    cr_assert_eq(hv_poi_axis_compose(&b, &a, &c), HV_OK);
    for (int o = 0; o < 23; ++o)
        for (int i = 0; i < 11; ++i) {
            double ref = 0;
            for (int k = 0; k < 17; ++k) ref += axis_weight(&b, o, k) * axis_weight(&a, k, i);
            cr_assert(fabs(axis_weight(&c, o, i) - ref) < 1e-14, "C[%d][%d] %.17g vs %.17g", o, i,
                      axis_weight(&c, o, i), ref);
        }
    hv_poi_axis_free(&a);
    hv_poi_axis_free(&b);
    hv_poi_axis_free(&c);
}

Test(poi, general_step_is_overlap_over_covered_length)
{
    /* input cells [1 + 0.5 i, 1 + 0.5 (i+1)], output rows running down from 4 in steps of 0.3 */
    hv_poi_axis a;
    cr_assert_eq(hv_poi_axis_step(1.0, 0.5, 6, 4.0, -0.3, 10, &a), HV_OK);
    for (int o = 0; o < 10; ++o) {
        double hi = 4.0 - 0.3 * o, lo = hi - 0.3, total = 0, ov[6];
        for (int i = 0; i < 6; ++i) {
            ov[i] = fmax(0, fmin(hi, 1 + 0.5 * (i + 1)) - fmax(lo, 1 + 0.5 * i));
            total += ov[i];
        }
        for (int i = 0; i < 6; ++i) {
            double want = total > 0 ? ov[i] / total : 0;
            if (total == 0) /* outside: the nearest cell */
                want = i == (int)fmin(5, fmax(0, floor((0.5 * (lo + hi) - 1) / 0.5)));
            cr_expect(fabs(axis_weight(&a, o, i) - want) < 1e-12, "out %d in %d: %.17g vs %.17g", o, i,
                      axis_weight(&a, o, i), want);
        }
    }
    hv_poi_axis_free(&a);
}

/* Wu's repeated resampling: one exact up-sampling step keeps the old pixels as blocks (the
 * value of a linear ramp is off by up to half an old pixel), while the chain of small steps
 * averages at every step and comes out much closer to the ramp: why the pipeline steps. */
Test(poi, steps_approach_linear_fields)
{
    int sw = 12, dw = 12 * 9;
    float src[12], one[108], steps[108];
    for (int i = 0; i < sw; ++i) src[i] = (float)((i + 0.5) / sw);
    cr_assert_eq(hv_poi_resample_steps(src, sw, 1, one, dw, 1, 1.0), HV_OK);
    cr_assert_eq(hv_poi_resample_steps(src, sw, 1, steps, dw, 1, 1.5), HV_OK);
    double e1 = 0, es = 0, m1 = 0, ms = 0;
    int n = 0;
    for (int x = 3 * 9; x < dw - 3 * 9; ++x) {
        double want = (x + 0.5) / dw;
        e1 = fmax(e1, fabs(one[x] - want));
        es = fmax(es, fabs(steps[x] - want));
        m1 += fabs(one[x] - want);
        ms += fabs(steps[x] - want);
        ++n;
    }
    m1 /= n;
    ms /= n;
    double px = 1.0 / sw;
    cr_expect(e1 > 0.4 * px, "one step is blocky: max error %.3g old pixels", e1 / px);
    cr_expect(es < 0.2 * px, "steps: max error %.3g old pixels (one step %.3g)", es / px, e1 / px);
    cr_expect(ms < 0.4 * m1, "steps: mean error %.3g old pixels (one step %.3g)", ms / px, m1 / px);
}

Test(poi, bad_arguments)
{
    float a[4] = {0}, b[4];
    cr_expect_eq(hv_poi_resample(NULL, 2, 2, b, 2, 2), HV_ERR_INVALID);
    cr_expect_eq(hv_poi_resample(a, 0, 2, b, 2, 2), HV_ERR_INVALID);
    cr_expect_eq(hv_poi_resample(a, 2, 2, b, 2, -1), HV_ERR_INVALID);
    cr_expect_eq(hv_poi_resample_steps(a, 2, 2, b, 2, 2, NAN), HV_ERR_INVALID);
}
