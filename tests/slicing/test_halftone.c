/* tests/slicing/test_halftone.c - halftoning: the void-and-cluster mask is a deterministic
 * permutation with blue-noise statistics (even box counts, no clumps), it is cached on disk;
 * both halftoners hit a uniform mixture within 1% in every 32x32x32 block. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "slicing/layers_internal.h"
#include "hovox/layers.h"
#include "support/support.h"

static int is_permutation(const uint32_t *r, size_t n)
{
    uint8_t *seen = calloc(n, 1);
    int ok = 1;
    for (size_t i = 0; i < n && ok; ++i) {
        if (r[i] >= n || seen[r[i]]) ok = 0;
        else seen[r[i]] = 1;
    }
    free(seen);
    return ok;
}

Test(bluenoise, deterministic_permutation)
{
    size_t n = 16 * 16 * 8;
    uint32_t *a = malloc(n * 4), *b = malloc(n * 4), *c = malloc(n * 4);
    cr_assert_eq(hv_bluenoise_generate(16, 16, 8, 1.5, 7, a, NULL), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_bluenoise_generate(16, 16, 8, 1.5, 7, b, NULL), HV_OK);
    cr_assert_eq(hv_bluenoise_generate(16, 16, 8, 1.5, 8, c, NULL), HV_OK);
    cr_expect(is_permutation(a, n));
    cr_expect(is_permutation(c, n));
    cr_expect_eq(memcmp(a, b, n * 4), 0, "same arguments, same mask");
    cr_expect_neq(memcmp(a, c, n * 4), 0, "another seed, another mask");
    cr_expect_eq(hv_bluenoise_generate(1, 16, 8, 1.5, 7, a, NULL), HV_ERR_INVALID);
    cr_expect_eq(hv_bluenoise_generate(16, 16, 8, 0.1, 7, a, NULL), HV_ERR_INVALID);
    free(a);
    free(b);
    free(c);
}

/* Variance of the number of ones in 4x4x4 boxes of the pattern "rank < level": blue noise
 * spreads the ones evenly (much less than the binomial variance of white noise). */
static double box_variance(const uint32_t *r, int nx, int ny, int nz, double level, double *mean)
{
    double s = 0, s2 = 0;
    int boxes = 0;
    uint32_t th = (uint32_t)(level * nx * ny * nz);
    for (int bz = 0; bz < nz; bz += 4)
        for (int by = 0; by < ny; by += 4)
            for (int bx = 0; bx < nx; bx += 4) {
                int k = 0;
                for (int z = bz; z < bz + 4; ++z)
                    for (int y = by; y < by + 4; ++y)
                        for (int x = bx; x < bx + 4; ++x) k += r[((size_t)z * ny + y) * nx + x] < th;
                s += k;
                s2 += (double)k * k;
                ++boxes;
            }
    *mean = s / boxes;
    return s2 / boxes - *mean * *mean;
}

Test(bluenoise, tile_is_blue_and_cached, .timeout = 300)
{
    const char *dir = t_tmpfile("cache");
    const uint32_t *r = NULL;
    int cached = -1;
    cr_assert_eq(hv_bluenoise_tile(dir, NULL, &r, &cached), HV_OK, "%s", hv_last_error());
    cr_expect_eq(cached, 0, "generated on first use");
    size_t n = (size_t)HV_BLUENOISE_NX * HV_BLUENOISE_NY * HV_BLUENOISE_NZ;
    cr_expect(is_permutation(r, n));
    char path[1024];
    snprintf(path, sizeof path, "%s/bluenoise-64x64x32-s1.5-v1.bin", dir);
    struct stat sb;
    cr_expect(stat(path, &sb) == 0 && (size_t)sb.st_size == 32 + 4 * n, "cache file %s written", path);
    const uint32_t *again = NULL;
    cr_assert_eq(hv_bluenoise_tile(dir, NULL, &again, &cached), HV_OK);
    cr_expect(again == r && cached == 1);
    for (int k = 0; k < 3; ++k) {
        double level = (double[]){0.05, 0.25, 0.5}[k], mean;
        double var = box_variance(r, HV_BLUENOISE_NX, HV_BLUENOISE_NY, HV_BLUENOISE_NZ, level, &mean);
        double white = 64 * level * (1 - level); /* binomial variance of 64 cells */
        cr_expect(var < 0.35 * white, "level %.2f: box variance %.3f, white noise %.3f", level, var, white);
        cr_expect(fabs(mean - 64 * level) < 0.5);
    }
}

/* a uniform mixture over a 96 x 96 x 64 block of layers, halftoned as the pipeline does */
static void uniform_blocks(const double *target, int m, int diffusion)
{
    int w = 96, h = 96, layers = 64;
    size_t plane = (size_t)w * h;
    float *frac = malloc(sizeof(float) * plane * m);
    float *err = calloc(plane * m, sizeof(float)), *next = calloc(plane * m, sizeof(float));
    uint8_t *mask = malloc(plane), *out = malloc(plane);
    memset(mask, 1, plane);
    for (int j = 0; j < m; ++j)
        for (size_t p = 0; p < plane; ++p) frac[j * plane + p] = (float)target[j];
    const uint32_t *ranks = NULL;
    int off[3];
    hv_bluenoise_offsets(3, off);
    if (!diffusion) cr_assert_eq(hv_bluenoise_tile(t_tmpfile("cache"), NULL, &ranks, NULL), HV_OK);
    /* counts per 32^3 block and material */
    uint64_t counts[3][3][2][8];
    memset(counts, 0, sizeof counts);
    uint64_t tot[8] = {0};
    for (int z = 0; z < layers; ++z) {
        uint64_t c[8] = {0};
        if (diffusion) {
            if (z % HV_HALFTONE_BLOCK == 0)
                hv_halftone_diffuse_start(frac, m, w, h, mask, &err, &next, 3, (size_t)z / HV_HALFTONE_BLOCK, z & 1,
                                          out);
            hv_halftone_diffuse(frac, m, w, h, mask, err, next, z & 1, out, c, NULL);
            float *t = err;
            err = next;
            next = t;
        } else {
            hv_halftone_bluenoise(frac, m, w, h, mask, ranks, off, (size_t)z, out, c, NULL);
        }
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                int k = out[y * w + x];
                cr_assert(k >= 1 && k <= m);
                counts[x / 32][y / 32][z / 32][k - 1]++;
            }
        for (int j = 0; j < m; ++j) tot[j] += c[j];
    }
    double worst = 0;
    for (int bx = 0; bx < 3; ++bx)
        for (int by = 0; by < 3; ++by)
            for (int bz = 0; bz < 2; ++bz)
                for (int j = 0; j < m; ++j) {
                    double a = counts[bx][by][bz][j] / 32768.0;
                    worst = fmax(worst, fabs(a - target[j]));
                    cr_expect(fabs(a - target[j]) <= 0.01, "%s: block (%d,%d,%d) material %d: %.4f, target %.4f",
                              diffusion ? "error diffusion" : "blue noise", bx, by, bz, j, a, target[j]);
                }
    for (int j = 0; j < m; ++j)
        cr_expect(fabs(tot[j] / (double)(plane * layers) - target[j]) < 0.002, "overall material %d: %.5f vs %.5f", j, tot[j] / (double)(plane * layers), target[j]);
    cr_log_info("%s: worst block deviation %.5f", diffusion ? "error diffusion" : "blue noise", worst);
    free(frac);
    free(err);
    free(next);
    free(mask);
    free(out);
}

Test(halftone, bluenoise_uniform_within_one_percent_per_block, .timeout = 300)
{
    double a[3] = {0.2, 0.3, 0.5}, b[3] = {0.05, 0.15, 0.8}, c[2] = {0.37, 0.63};
    uniform_blocks(a, 3, 0);
    uniform_blocks(b, 3, 0);
    uniform_blocks(c, 2, 0);
}

Test(halftone, diffusion_uniform_within_one_percent_per_block)
{
    double a[3] = {0.2, 0.3, 0.5}, b[3] = {0.05, 0.15, 0.8}, c[2] = {0.37, 0.63};
    uniform_blocks(a, 3, 1);
    uniform_blocks(b, 3, 1);
    uniform_blocks(c, 2, 1);
}

Test(halftone, diffusion_keeps_to_an_irregular_mask)
{
    /* a disc with a hole: error only travels between object pixels */
    int w = 120, h = 80, m = 3;
    size_t plane = (size_t)w * h;
    float *frac = malloc(sizeof(float) * plane * m), *err = calloc(plane * m, 4), *next = calloc(plane * m, 4);
    uint8_t *mask = malloc(plane), *out = malloc(plane);
    size_t inside = 0;
    double want[3] = {0};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t p = (size_t)y * w + x;
            double r = hypot(x - 60.0, (y - 40.0) * 1.5);
            mask[p] = r < 38 && r > 9;
            double a = 0.5 * x / w, b = 0.3 * y / h;
            frac[p] = (float)a;
            frac[plane + p] = (float)b;
            frac[2 * plane + p] = (float)(1 - a - b);
            if (mask[p]) {
                ++inside;
                want[0] += a;
                want[1] += b;
                want[2] += 1 - a - b;
            }
        }
    uint64_t got[3] = {0, 0, 0};
    for (int z = 0; z < 16; ++z) {
        hv_halftone_diffuse(frac, m, w, h, mask, err, next, z & 1, out, got, NULL);
        float *t = err;
        err = next;
        next = t;
        for (size_t p = 0; p < plane; ++p) cr_assert_eq(out[p] != 0, mask[p] != 0);
    }
    for (int j = 0; j < m; ++j) {
        double a = got[j] / (16.0 * inside), t = want[j] / inside;
        cr_expect(fabs(a - t) < 0.005, "material %d: %.4f vs %.4f", j, a, t);
    }
    free(frac);
    free(err);
    free(next);
    free(mask);
    free(out);
}

Test(halftone, bluenoise_offsets_follow_the_seed)
{
    int a[3], b[3], c[3];
    hv_bluenoise_offsets(0, a);
    hv_bluenoise_offsets(1, b);
    hv_bluenoise_offsets(1, c);
    cr_expect(a[0] == 0 && a[1] == 0 && a[2] == 0);
    cr_expect(memcmp(b, c, sizeof b) == 0);
    for (int k = 0; k < 3; ++k) cr_expect(b[k] >= 0 && b[k] < (k < 2 ? 64 : 32));
}

/* The blue-noise kernel (vectorised, in runs) against its definition pixel by pixel: material j
 * where p_0 + .. + p_{j-1} <= t < p_0 + .. + p_j, a zero last fraction skipped for the last
 * material present. Random fractions with zeros, a ragged mask, widths that are no multiple of
 * the tile or the vector, every material count up to 9 (the unrolled 1..8 and the general path);
 * the target sums to the bit as summed pixel after pixel. */
Test(halftone, bluenoise_matches_its_definition_per_pixel, .timeout = 300)
{
    const uint32_t *ranks = NULL;
    cr_assert_eq(hv_bluenoise_tile(t_tmpfile("cache"), NULL, &ranks, NULL), HV_OK);
    const float inv = 1.0f / (float)(HV_BLUENOISE_NX * HV_BLUENOISE_NY * HV_BLUENOISE_NZ);
    uint64_t rng = 12345;
    for (int m = 1; m <= 9; ++m) {
        int w = 1100 + 37 * m, h = 23;
        size_t plane = (size_t)w * h;
        float *frac = malloc(sizeof(float) * plane * m);
        uint8_t *mask = malloc(plane), *out = malloc(plane);
        for (size_t p = 0; p < plane; ++p) {
            int y = (int)(p / (size_t)w), x = (int)(p % (size_t)w);
            /* rows empty, full, or a band whose ends move */
            mask[p] = y % 7 == 3 ? 0 : y % 5 == 0 ? 1 : (x > 3 * y && x < w - 11 * y);
            double s = 0, v[9];
            for (int j = 0; j < m; ++j) {
                rng = rng * 6364136223846793005ull + 1442695040888963407ull;
                v[j] = (rng >> 40) % 4 == 0 ? 0 : (double)(rng >> 11) / 9007199254740992.0;
                s += v[j];
            }
            for (int j = 0; j < m; ++j) frac[j * plane + p] = s > 0 ? (float)(v[j] / s) : j == 0;
        }
        int off[3];
        hv_bluenoise_offsets((uint64_t)m, off);
        for (int z = 0; z < 3; ++z) {
            uint64_t counts[9] = {0}, want[9] = {0};
            double tsum[9] = {0}, wsum[9] = {0};
            hv_halftone_bluenoise(frac, m, w, h, mask, ranks, off, (size_t)z, out, counts, tsum);
            int zz = (z + off[2]) % HV_BLUENOISE_NZ;
            for (size_t p = 0; p < plane; ++p) {
                int y = (int)(p / (size_t)w), x = (int)(p % (size_t)w);
                int k = 0;
                if (mask[p]) {
                    float t = ((float)ranks[((size_t)zz * HV_BLUENOISE_NY + (size_t)((y + off[1]) % HV_BLUENOISE_NY)) *
                                                HV_BLUENOISE_NX + (size_t)((x + off[0]) & (HV_BLUENOISE_NX - 1))] + 0.5f) * inv;
                    float cu = 0;
                    for (int j = 0; j < m - 1; ++j) {
                        cu += frac[j * plane + p];
                        k += t >= cu;
                    }
                    if (k == m - 1 && frac[(m - 1) * plane + p] <= 0)
                        for (int j = m - 1; j >= 0; --j)
                            if (frac[j * plane + p] > 0) {
                                k = j;
                                break;
                            }
                    want[k]++;
                    for (int j = 0; j < m; ++j) wsum[j] += frac[j * plane + p];
                    ++k;
                }
                cr_assert_eq(out[p], k, "m %d layer %d pixel (%d, %d): %d, defined %d", m, z, x, y, out[p], k);
            }
            /* the target to the bit: per row a float sum in pixel order, the rows' sums added in double */
            double exact[9] = {0};
            for (int y = 0; y < h; ++y)
                for (int j = 0; j < m; ++j) {
                    float s = 0;
                    for (int x = 0; x < w; ++x)
                        if (mask[(size_t)y * w + x]) s += frac[j * plane + (size_t)y * w + x];
                    exact[j] += s;
                }
            for (int j = 0; j < m; ++j) {
                cr_expect(tsum[j] == exact[j], "m %d material %d: target %.17g, in pixel order %.17g", m, j, tsum[j],
                          exact[j]);
                cr_expect_eq(counts[j], want[j], "m %d material %d: count %llu, defined %llu", m, j,
                             (unsigned long long)counts[j], (unsigned long long)want[j]);
                cr_expect(fabs(tsum[j] - wsum[j]) <= 1e-4 * wsum[j] + 1e-3, "m %d material %d: target %g vs %g", m, j,
                          tsum[j], wsum[j]);
            }
        }
        free(frac);
        free(mask);
        free(out);
    }
}
