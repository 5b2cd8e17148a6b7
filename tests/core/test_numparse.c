/* tests/core/test_numparse.c - hv_parse_float (src/core/numparse.c) against strtof: the same
 * float (bit for bit) and the same verdict on millions of random decimals of every shape the
 * 3MF reader meets, on float midpoints, near the ends of the float range, and on malformed text. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"

static void same(const char *s)
{
    size_t n = strlen(s);
    char *end;
    float want = strtof(s, &end);
    const char *rest = end; /* white space after the number is taken, as strtof takes it before */
    while (rest < s + n && (*rest == ' ' || *rest == '\t' || *rest == '\n' || *rest == '\r')) ++rest;
    int ok_want = n > 0 && end != s && rest == s + n;
    float got = 0;
    int ok_got = hv_parse_float(s, n, &got);
    cr_assert_eq(ok_got, ok_want, "'%s': taken %d, strtof %d", s, ok_got, ok_want);
    if (ok_want) {
        uint32_t a, b;
        memcpy(&a, &want, 4);
        memcpy(&b, &got, 4);
        cr_assert(a == b || (want != want && got != got), "'%s': %a, strtof %a", s, (double)got, (double)want);
    }
}

static uint64_t g_state = 88172645463325252ull;
static uint64_t rnd(void)
{
    g_state ^= g_state << 13;
    g_state ^= g_state >> 7;
    g_state ^= g_state << 17;
    return g_state;
}

Test(numparse, random_decimals_match_strtof)
{
    char s[96];
    for (int i = 0; i < 2000000; ++i) {
        int nd = 1 + (int)(rnd() % 20), dot = (int)(rnd() % (unsigned)(nd + 2)) - 1, at = 0;
        if (rnd() % 3 == 0) s[at++] = rnd() % 2 ? '-' : '+';
        for (int k = 0; k < nd; ++k) {
            if (k == dot) s[at++] = '.';
            s[at++] = (char)('0' + rnd() % 10);
        }
        if (rnd() % 4 == 0) at += snprintf(s + at, sizeof s - (size_t)at, "e%d", (int)(rnd() % 90) - 45);
        s[at] = '\0';
        same(s);
    }
}

Test(numparse, printed_floats_and_midpoints)
{
    char s[64];
    for (int i = 0; i < 1000000; ++i) {
        uint32_t bits = (uint32_t)rnd();
        float f;
        memcpy(&f, &bits, 4);
        if (f != f) continue;
        snprintf(s, sizeof s, "%.*g", 6 + (int)(rnd() % 12), (double)f); /* six decimals, as lib3mf */
        same(s);
        /* the decimal of the midpoint between f and the next float: ties to even */
        double mid = ((double)f + (double)nextafterf(f, INFINITY)) / 2;
        snprintf(s, sizeof s, "%.17g", mid);
        same(s);
        snprintf(s, sizeof s, "%.6f", (double)f);
        same(s);
    }
}

Test(numparse, edges_and_malformed_text)
{
    static const char *const cases[] = {
        "0", "-0", "+0", "0.0", "-0.0", ".5", "5.", "1e5", "1E-5", "1e+5", "1e22", "1e23", "9007199254740993", "9007199254740992",
        "3.4028234e38", "3.4028236e38", "3.5e38", "1e39", "1.17549435e-38", "1.4e-45", "7e-46", "1e-50",
        "0.000000000000000000000000000000000000000000001", "16777217", "16777216.5", "33554433",
        "12345678901234567890", "1234567890123456789", "0.1", "0.2", "0.3", "123.456789", "-98.765432",
        "", " ", " 1", "1 ", "1e", "1e+", "e5", ".", "-", "+", "-.", "1.2.3", "1e5.5", "0x10", "inf", "-inf", "nan",
        "infinity", "1,5", "--1", "1-", "0e99999", "1e-99999", "1e99999", "00000000000000000000000001.5",
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) same(cases[i]);
}

/* 3MF Core 2.3.4: an ST_Number collapses white space, so " 1.5 " is a coordinate (a producer's
 * padded columns); before, white space after the number was refused ("x is not a finite number"). */
Test(numparse, white_space_around_a_number)
{
    static const struct {
        const char *s;
        int ok;
        float v;
    } cases[] = {
        {"1.5 ", 1, 1.5f}, {" 1.5 ", 1, 1.5f}, {"\t-2e3\n", 1, -2000.0f}, {"0 \r\n", 1, 0.0f}, {" +.25\t\t", 1, 0.25f},
        {"1 x", 0, 0}, {"1 1", 0, 0}, {" ", 0, 0}, {" \t\n", 0, 0}, {"1\v", 0, 0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
        float got = -1;
        int ok = hv_parse_float(cases[i].s, strlen(cases[i].s), &got);
        cr_assert_eq(ok, cases[i].ok, "case %zu: taken %d", i, ok);
        if (ok) cr_assert_eq(got, cases[i].v, "case %zu: %g", i, (double)got);
        same(cases[i].s);
    }
}
