/* tests/colour/test_colour.c - colour maps (hovox/colour.h): CIEDE2000 against Sharma, Wu and Dalal's
 * published test pairs (2005, table 1), the mixing rule's invariants (fractions sum to 1, alpha to
 * clear, white where ink is short), the cache giving the same answer from many threads, an input
 * profile equal to sRGB giving sRGB's fractions, what fractions print landing near the colour asked
 * for inside the gamut, and each refusal. (Fractions against LittleCMS called independently:
 * tests/colour/check_littlecms.py, run by the CLI case colour_matches_littlecms.) */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/colour.h"
#include "support/support.h"

Test(colour, ciede2000_matches_sharmas_test_pairs)
{
    static const double pairs[][7] = {
        {50.0000, 2.6772, -79.7751, 50.0000, 0.0000, -82.7485, 2.0425},
        {50.0000, 3.1571, -77.2803, 50.0000, 0.0000, -82.7485, 2.8615},
        {50.0000, 2.8361, -74.0200, 50.0000, 0.0000, -82.7485, 3.4412},
        {50.0000, 0.0000, 0.0000, 50.0000, -1.0000, 2.0000, 2.3669},
        {50.0000, 2.5000, 0.0000, 73.0000, 25.0000, -18.0000, 27.1492},
        {60.2574, -34.0099, 36.2677, 60.4626, -34.1751, 39.4387, 1.2644},
    };
    for (size_t i = 0; i < sizeof pairs / sizeof pairs[0]; ++i) {
        double de = hv_colour_delta_e2000(pairs[i], pairs[i] + 3);
        cr_assert(fabs(de - pairs[i][6]) < 1e-4, "pair %zu: %.4f, published %.4f", i + 1, de, pairs[i][6]);
        cr_assert(fabs(hv_colour_delta_e2000(pairs[i] + 3, pairs[i]) - de) < 1e-9); /* symmetric */
    }
}

static hv_colour_map *default_map(void)
{
    hv_colour_map *m = NULL;
    cr_assert_eq(hv_colour_map_create(NULL, &m), HV_OK, "%s", hv_last_error());
    return m;
}

Test(colour, fractions_sum_to_one_with_white_and_clear_by_the_rule)
{
    hv_colour_map *m = default_map();
    cr_assert_str_eq(hv_colour_map_icc(m), hv_colour_default_icc());
    cr_assert_str_eq(hv_colour_map_description(m), "Artifex CMYK SWOP Profile");
    cr_assert_str_eq(hv_colour_map_resin(m, HV_COLOUR_W), "VeroPureWhite");
    cr_assert_str_eq(hv_colour_map_resin(m, HV_COLOUR_CLEAR), "VeroClear");
    for (int r = 0; r < 256; r += 15)
        for (int g = 0; g < 256; g += 30)
            for (int b = 0; b < 256; b += 45) {
                uint8_t c[4] = {(uint8_t)r, (uint8_t)g, (uint8_t)b, 255};
                float f[HV_COLOUR_SLOTS];
                hv_colour_map_fractions(m, c, f);
                double sum = 0, ink = 0;
                for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
                    cr_assert(f[k] >= 0 && f[k] <= 1);
                    sum += f[k];
                }
                for (int k = 0; k < 4; ++k) ink += f[k];
                cr_assert(fabs(sum - 1) < 1e-5, "%d,%d,%d: sum %g", r, g, b, sum);
                cr_assert_eq(f[HV_COLOUR_CLEAR], 0);
                cr_assert(fabs(f[HV_COLOUR_W] - (ink < 1 ? 1 - ink : 0)) < 1e-5);
            }
    float f[HV_COLOUR_SLOTS];
    hv_colour_map_fractions(m, (const uint8_t[4]){255, 255, 255, 255}, f);
    cr_assert(f[HV_COLOUR_W] > 0.99, "white: %g white", (double)f[HV_COLOUR_W]);
    hv_colour_map_fractions(m, (const uint8_t[4]){0, 0, 0, 255}, f);
    cr_assert_eq(f[HV_COLOUR_W], 0); /* a rich black: coverage beyond 100 % scaled to fit */
    cr_assert(f[HV_COLOUR_K] > f[HV_COLOUR_C] && f[HV_COLOUR_K] > 0.25);
    float half[HV_COLOUR_SLOTS];
    hv_colour_map_fractions(m, (const uint8_t[4]){255, 0, 0, 255}, f);
    hv_colour_map_fractions(m, (const uint8_t[4]){255, 0, 0, 51}, half);
    cr_assert(fabs(half[HV_COLOUR_CLEAR] - 0.8) < 1e-6);
    for (int k = 0; k < HV_COLOUR_CLEAR; ++k) cr_assert(fabs(half[k] - 0.2 * f[k]) < 1e-6);
    hv_colour_map_fractions(m, (const uint8_t[4]){0, 0, 0, 0}, f);
    cr_assert_eq(f[HV_COLOUR_CLEAR], 1);
    hv_colour_map_destroy(m);
}

Test(colour, printed_colours_land_near_the_colour_asked_for)
{
    hv_colour_options o;
    hv_colour_options_init(&o);
    o.intent = HV_INTENT_RELATIVE; /* the intent the printed colour is measured with */
    hv_colour_map *m = NULL;
    cr_assert_eq(hv_colour_map_create(&o, &m), HV_OK, "%s", hv_last_error());
    /* light colours take less than 100 % ink (white fills the rest): the fractions print the
     * coverage the profile asked for, and the colour comes back within a few tenths of a unit */
    static const uint8_t light[][3] = {{200, 200, 180}, {220, 180, 160}, {180, 200, 220}, {230, 230, 230}};
    for (size_t i = 0; i < 4; ++i) {
        uint8_t c[4] = {light[i][0], light[i][1], light[i][2], 255};
        float f[HV_COLOUR_SLOTS];
        double want[3], got[3];
        hv_colour_map_fractions(m, c, f);
        cr_assert_gt(f[HV_COLOUR_W], 0);
        hv_colour_map_lab_of_srgb(m, c, want);
        hv_colour_map_lab_of_fractions(m, f, got);
        double de = hv_colour_delta_e2000(want, got);
        cr_assert(de < 2, "%u,%u,%u: dE2000 %.2f", c[0], c[1], c[2], de);
    }
    /* a saturated sRGB green lies outside the press gamut: a real difference, reported */
    uint8_t green[4] = {0, 255, 0, 255};
    float f[HV_COLOUR_SLOTS];
    double want[3], got[3];
    hv_colour_map_fractions(m, green, f);
    hv_colour_map_lab_of_srgb(m, green, want);
    hv_colour_map_lab_of_fractions(m, f, got);
    cr_assert_gt(hv_colour_delta_e2000(want, got), 10);
    hv_colour_map_destroy(m);
}

typedef struct worker_arg {
    hv_colour_map *m;
    int seed;
    int bad;
} worker_arg;

#include <pthread.h>
static void *worker(void *p)
{
    worker_arg *a = p;
    uint32_t x = (uint32_t)a->seed * 2654435761u + 1;
    for (int i = 0; i < 20000; ++i) {
        x = x * 1664525u + 1013904223u;
        uint8_t c[4] = {(uint8_t)(x >> 24), (uint8_t)(x >> 16), (uint8_t)((x >> 8) & 0xF0), 255};
        float f[HV_COLOUR_SLOTS], g[HV_COLOUR_SLOTS];
        hv_colour_map_fractions(a->m, c, f);
        hv_colour_map_fractions(a->m, c, g);
        if (memcmp(f, g, sizeof f) != 0) a->bad = 1;
    }
    return NULL;
}

Test(colour, the_cache_answers_the_same_from_many_threads)
{
    hv_colour_map *m = default_map(), *fresh = default_map();
    pthread_t t[4];
    worker_arg a[4];
    for (int i = 0; i < 4; ++i) {
        a[i] = (worker_arg){m, i, 0};
        pthread_create(&t[i], NULL, worker, &a[i]);
    }
    for (int i = 0; i < 4; ++i) {
        pthread_join(t[i], NULL);
        cr_assert_not(a[i].bad);
    }
    /* the cached answers are the uncached ones */
    for (int i = 0; i < 256; ++i) {
        uint8_t c[4] = {(uint8_t)i, (uint8_t)(255 - i), (uint8_t)(i * 7), 255};
        float f[HV_COLOUR_SLOTS], g[HV_COLOUR_SLOTS];
        hv_colour_map_fractions(m, c, f);
        hv_colour_map_fractions(m, c, f);
        hv_colour_map_fractions(fresh, c, g);
        cr_assert_eq(memcmp(f, g, sizeof f), 0);
    }
    hv_colour_map_destroy(m);
    hv_colour_map_destroy(fresh);
}

Test(colour, an_input_profile_that_is_srgb_gives_srgbs_fractions)
{
    hv_colour_map *m = default_map();
    size_t n = 0;
    char *icc = t_slurp("/usr/share/color/icc/ghostscript/srgb.icc", &n);
    int id = -1;
    cr_assert_eq(hv_colour_map_add_input(m, icc, n, "skin.png", &id), HV_OK, "%s", hv_last_error());
    cr_assert_eq(id, 1);
    uint8_t c[4] = {200, 120, 60, 255};
    float f[HV_COLOUR_SLOTS], g[HV_COLOUR_SLOTS];
    hv_colour_map_fractions(m, c, f);
    hv_colour_map_fractions_in(m, id, c, g);
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) cr_assert(fabs(f[k] - g[k]) < 0.01, "slot %d: %g vs %g", k, (double)f[k], (double)g[k]);
    free(icc);
    cr_assert_eq(hv_colour_map_add_input(m, "junk", 4, "skin.png", &id), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(),
                     "skin.png: its embedded colour profile is not an ICC profile (4 bytes, shorter than the 128-byte header)");
    icc = t_slurp(hv_colour_default_icc(), &n);
    cr_assert_eq(hv_colour_map_add_input(m, icc, n, "skin.jpg", &id), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(), "skin.jpg: its embedded colour profile is CMYK, not RGB or grey");
    free(icc);
    hv_colour_map_destroy(m);
}

/* Review item 2: what is no ICC profile is refused in one message that names the file, what is
 * wrong and the value (LittleCMS said "not an ICC profile: not an ICC profile, invalid signature"). */
static void write_bytes(const char *path, const char *d, size_t n)
{
    FILE *fp = fopen(path, "wb");
    cr_assert_not_null(fp);
    cr_assert_eq(fwrite(d, 1, n, fp), n);
    fclose(fp);
}

Test(colour, what_is_no_icc_profile_is_refused_in_one_message)
{
    size_t n = 0;
    char *good = t_slurp(hv_colour_default_icc(), &n);
    cr_assert(n > 400);
    hv_colour_map *m = NULL;
    hv_colour_options o;
    hv_colour_options_init(&o);
    char *bad = malloc(n);
    char want[1300];
    const char *path = t_tmpfile("bad.icc");
    o.icc = path;
    /* shorter than the header */
    write_bytes(path, "not a profile", 13);
    cr_assert_eq(hv_colour_map_create(&o, &m), HV_ERR_BAD_INPUT);
    snprintf(want, sizeof want, "%s: not an ICC profile (13 bytes, shorter than the 128-byte header)", path);
    cr_assert_str_eq(hv_last_error(), want);
    /* no signature (was: "not an ICC profile: not an ICC profile, invalid signature") */
    memcpy(bad, good, n);
    memcpy(bad + 36, "ab\x01\"", 4);
    write_bytes(path, bad, n);
    cr_assert_eq(hv_colour_map_create(&o, &m), HV_ERR_BAD_INPUT);
    snprintf(want, sizeof want, "%s: not an ICC profile (bytes 36-39 are \"ab\\x01\\x22\", not the signature \"acsp\")",
             path);
    cr_assert_str_eq(hv_last_error(), want);
    /* cut short: was "the profile has no perceptual intent for output" */
    write_bytes(path, good, 400);
    cr_assert_eq(hv_colour_map_create(&o, &m), HV_ERR_BAD_INPUT);
    snprintf(want, sizeof want, "%s: a truncated ICC profile (its header gives %zu bytes, the file has 400)", path, n);
    cr_assert_str_eq(hv_last_error(), want);
    /* a tag table LittleCMS refuses: its reason */
    memcpy(bad, good, n);
    memcpy(bad + 128, "\0\0\x27\x0f", 4); /* 9999 tags */
    write_bytes(path, bad, n);
    cr_assert_eq(hv_colour_map_create(&o, &m), HV_ERR_BAD_INPUT);
    snprintf(want, sizeof want, "%s: a damaged ICC profile (LittleCMS: Too many tags (9999))", path);
    cr_assert_str_eq(hv_last_error(), want);
    cr_assert_null(m);
    /* the same for a texture's embedded profile */
    cr_assert_eq(hv_colour_map_create(NULL, &m), HV_OK, "%s", hv_last_error());
    int id = -1;
    cr_assert_eq(hv_colour_map_add_input(m, good, 400, "skin.png", &id), HV_ERR_BAD_INPUT);
    snprintf(want, sizeof want,
             "skin.png: its embedded colour profile is a truncated ICC profile (its header gives %zu bytes, there are 400)", n);
    cr_assert_str_eq(hv_last_error(), want);
    hv_colour_map_destroy(m);
    free(bad);
    free(good);
}

Test(colour, refusals)
{
    hv_colour_map *m = (hv_colour_map *)1;
    hv_colour_options o;
    hv_colour_options_init(&o);
    o.icc = "/usr/share/color/icc/ghostscript/srgb.icc";
    cr_assert_eq(hv_colour_map_create(&o, &m), HV_ERR_BAD_INPUT);
    cr_assert_null(m);
    cr_assert_str_eq(hv_last_error(),
                     "/usr/share/color/icc/ghostscript/srgb.icc: an RGB profile where a CMYK output profile is needed");
    o.icc = "/usr/share/color/icc/ghostscript/sgray.icc";
    cr_assert_eq(hv_colour_map_create(&o, &m), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(),
                     "/usr/share/color/icc/ghostscript/sgray.icc: a grey profile where a CMYK output profile is needed");
    const char *junk = t_tmpfile("junk.icc");
    FILE *fp = fopen(junk, "w");
    fputs("not a profile", fp);
    fclose(fp);
    o.icc = junk;
    cr_assert_eq(hv_colour_map_create(&o, &m), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "junk.icc: not an ICC profile"), "%s", hv_last_error());
    o.icc = t_tmpfile("none.icc");
    cr_assert_eq(hv_colour_map_create(&o, &m), HV_ERR_IO);
    o.icc = NULL;
    o.resins = "a,b,c,d,e";
    cr_assert_eq(hv_colour_map_create(&o, &m), HV_ERR_INVALID);
    o.resins = "a,b,,d,e,f";
    cr_assert_eq(hv_colour_map_create(&o, &m), HV_ERR_INVALID);
    o.resins = "a,b,c,d,e,f,g";
    cr_assert_eq(hv_colour_map_create(&o, &m), HV_ERR_INVALID);
    o.resins = " C1, M1 ,Y1,K1,W1,Clear 1 ";
    cr_assert_eq(hv_colour_map_create(&o, &m), HV_OK, "%s", hv_last_error());
    cr_assert_str_eq(hv_colour_map_resin(m, 1), "M1");
    cr_assert_str_eq(hv_colour_map_resin(m, 5), "Clear 1");
    hv_colour_map_destroy(m);
    o.resins = NULL;
    o.intent = (hv_intent)7;
    cr_assert_eq(hv_colour_map_create(&o, &m), HV_ERR_INVALID);
    hv_colour_map_destroy(NULL);
}
