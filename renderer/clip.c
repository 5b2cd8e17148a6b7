/* renderer/clip.c - cut planes and boxes for the preview: "x>10", "z<5", "x>0&y>0" name the
 * convex region to remove (an intersection of half-spaces); boxes are six half-spaces. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/render.h"

static const char *skip_ws(const char *p)
{
    while (*p == ' ' || *p == '\t') ++p;
    return p;
}

hv_status hv_clip_parse(const char *expr, hv_clip *out)
{
    memset(out, 0, sizeof *out);
    const char *p = expr;
#define FAIL(what) \
    return hv_error_set(HV_ERR_INVALID, "clip '%s': column %d: %s", expr, (int)(p - expr) + 1, what)
    for (;;) {
        p = skip_ws(p);
        int axis;
        switch (*p) {
        case 'x': case 'X': axis = 0; break;
        case 'y': case 'Y': axis = 1; break;
        case 'z': case 'Z': axis = 2; break;
        default: FAIL("axis x, y or z expected");
        }
        ++p;
        p = skip_ws(p);
        double sign;
        if (*p == '>') sign = 1;
        else if (*p == '<') sign = -1;
        else FAIL("'<' or '>' expected");
        ++p;
        if (*p == '=') ++p; /* >= and > remove the same region up to a set of measure zero */
        p = skip_ws(p);
        char *end;
        errno = 0;
        double v = strtod(p, &end);
        if (end == p) FAIL("number expected");
        if (errno == ERANGE || !isfinite(v)) FAIL("number out of range");
        if (out->planes == HV_CLIP_MAX_PLANES) FAIL("too many conditions (at most 8)");
        double *n = out->normal[out->planes];
        n[0] = n[1] = n[2] = 0;
        n[axis] = sign;
        out->offset[out->planes] = sign * v; /* sign*x > sign*v */
        out->planes++;
        p = skip_ws(end);
        if (*p == '\0') break;
        if (*p != '&' && *p != ',') FAIL("'&' or the end expected");
        ++p;
    }
#undef FAIL
    return HV_OK;
}

hv_status hv_clip_box(const double lo[3], const double hi[3], hv_clip *out)
{
    memset(out, 0, sizeof *out);
    for (int a = 0; a < 3; ++a)
        if (!isfinite(lo[a]) || !isfinite(hi[a]) || !(lo[a] < hi[a]))
            return hv_error_set(HV_ERR_INVALID,
                                "clip box: %c range [%g, %g] must be finite with low < high",
                                "xyz"[a], lo[a], hi[a]);
    out->planes = 6;
    for (int a = 0; a < 3; ++a) {
        out->normal[2 * a][a] = 1; /* x > lo */
        out->offset[2 * a] = lo[a];
        out->normal[2 * a + 1][a] = -1; /* x < hi */
        out->offset[2 * a + 1] = -hi[a];
    }
    return HV_OK;
}
