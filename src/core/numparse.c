/* src/core/numparse.c - decimal numbers from text without strtof's cost: the exact fast path of
 * Clinger (1990, "How to read floating point numbers accurately", section 4): a decimal of at
 * most 19 significant digits below 2^53 times a power of ten within 10^22 is one correctly
 * rounded double operation; that double rounds to the same float as the decimal unless it sits
 * on a midpoint between two floats, which, like every other form, goes to strtof. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"

static const double k_pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                   1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/* [+-]digits[.digits][(e|E)[+-]digits] with at least one mantissa digit; 0 when it is not that
 * form or outside the fast path. The digits run in tight loops (leading zeros apart, every digit
 * significant), so lib3mf's "-1.969596" costs no test a digit beyond its value (issue 26). */
static int fast_path(const char *p, const char *e, double *out)
{
    int neg = 0, exp10 = 0;
    uint64_t w = 0; /* wraps past 19 digits, which are refused below */
    if (p < e && (*p == '-' || *p == '+')) neg = *p++ == '-';
    const char *m = p;
    while (p < e && *p == '0') ++p; /* leading zeros count for nothing */
    const char *q = p;
    for (unsigned d; p < e && (d = (unsigned)(unsigned char)*p - '0') < 10; ++p) w = w * 10 + d;
    ptrdiff_t nd = p - q;
    int any = p > m;
    if (p < e && *p == '.') {
        const char *f = ++p;
        if (nd == 0)
            while (p < e && *p == '0') ++p; /* 0.000123: zeros before the first significant digit */
        const char *g = p;
        for (unsigned d; p < e && (d = (unsigned)(unsigned char)*p - '0') < 10; ++p) w = w * 10 + d;
        nd += p - g;
        exp10 = -(int)HV_MIN(p - f, (ptrdiff_t)100000);
        any |= p > f;
    }
    if (!any || nd > 19) return 0;
    if (p < e && (*p == 'e' || *p == 'E')) {
        int eneg = 0, en = 0, edig = 0;
        ++p;
        if (p < e && (*p == '-' || *p == '+')) eneg = *p++ == '-';
        for (; p < e && *p >= '0' && *p <= '9'; ++p, ++edig)
            if (en < 10000) en = en * 10 + (*p - '0');
        if (!edig) return 0;
        exp10 += eneg ? -en : en;
    }
    if (p != e || w > ((uint64_t)1 << 53)) return 0;
    double d = (double)w;
    if (w && (exp10 < -22 || exp10 > 22)) return 0;
    if (w) d = exp10 < 0 ? d / k_pow10[-exp10] : d * k_pow10[exp10];
    *out = neg ? -d : d;
    return 1;
}

int hv_parse_float(const char *s, size_t len, float *out)
{
    double d;
    if (fast_path(s, s + len, &d)) {
        double a = fabs(d);
        uint64_t bits;
        memcpy(&bits, &d, sizeof bits);
        /* inside the float normal range and not on a float midpoint (the 29 bits of the double's
         * significand below a float's are exactly one half) */
        if (a == 0 || (a >= 0x1p-125 && a <= 0x1p127 && (bits & 0x1FFFFFFFu) != 0x10000000u)) {
            *out = (float)d;
            return 1;
        }
    }
    char buf[128], *end;
    /* white space after the number, as strtof takes it before: an XML Schema number (3MF's
     * ST_Number, an xs:double) collapses white space on both sides (3MF Core 2.3.4) */
    while (len > 0 && (s[len - 1] == ' ' || s[len - 1] == '\t' || s[len - 1] == '\n' || s[len - 1] == '\r')) --len;
    if (len == 0 || len >= sizeof buf) return 0;
    memcpy(buf, s, len);
    buf[len] = '\0';
    *out = strtof(buf, &end);
    return end == buf + len;
}
