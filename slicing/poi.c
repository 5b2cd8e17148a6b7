/* slicing/poi.c - pixel overlap interpolation (Wu 2.4.2, Fig. 17-18 and 21): pixels as
 * rectangles, a new pixel the area-weighted average of the old pixels it overlaps; separable
 * axis operators, exact for any ratio, composed for Wu's repeated resampling I0 -> ... -> Ik. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "layers_internal.h"

#define POI_MAX_SIDE (1 << 24)

void hv_poi_axis_free(hv_poi_axis *ax)
{
    if (!ax) return;
    free(ax->start);
    free(ax->len);
    free(ax->off);
    free(ax->w);
    memset(ax, 0, sizeof *ax);
}

static hv_status axis_alloc(hv_poi_axis *ax, int n_in, int n_out, size_t nw)
{
    memset(ax, 0, sizeof *ax);
    ax->n_in = n_in;
    ax->n_out = n_out;
    ax->start = hv_malloc_array((size_t)n_out, sizeof *ax->start);
    ax->len = hv_malloc_array((size_t)n_out, sizeof *ax->len);
    ax->off = hv_malloc_array((size_t)n_out, sizeof *ax->off);
    ax->w = hv_malloc_array(HV_MAX(nw, (size_t)1), sizeof *ax->w);
    if (!ax->start || !ax->len || !ax->off || !ax->w) {
        hv_poi_axis_free(ax);
        return HV_ERR_NOMEM;
    }
    return HV_OK;
}

/* Append weights for one output cell, trimming zero weights at both ends. */
static hv_status axis_push(hv_poi_axis *ax, size_t *cap, int o, int first, const double *w, int n)
{
    int a = 0, b = n;
    while (a < b && w[a] == 0) ++a;
    while (b > a && w[b - 1] == 0) --b;
    size_t at = o ? ax->off[o - 1] + (size_t)ax->len[o - 1] : 0;
    if (at + (size_t)(b - a) > *cap) {
        size_t nc = HV_MAX(*cap * 2, at + (size_t)(b - a));
        double *nw = hv_realloc(ax->w, nc * sizeof *nw);
        if (!nw) return HV_ERR_NOMEM;
        ax->w = nw;
        *cap = nc;
    }
    ax->start[o] = first + a;
    ax->len[o] = b - a;
    ax->off[o] = at;
    if (b > a) memcpy(ax->w + at, w + a, (size_t)(b - a) * sizeof *w);
    return HV_OK;
}

hv_status hv_poi_axis_step(double in_lo, double in_pitch, int n_in, double out_origin,
                           double out_pitch, int n_out, hv_poi_axis *ax)
{
    memset(ax, 0, sizeof *ax);
    if (n_in < 1 || n_out < 1 || !(in_pitch > 0) || !(out_pitch != 0) || !isfinite(in_lo) ||
        !isfinite(out_origin) || !isfinite(in_pitch) || !isfinite(out_pitch))
        return hv_error_set(HV_ERR_INVALID, "POI: bad axis (%d cells of %g from %g -> %d cells of %g from %g)",
                            n_in, in_pitch, in_lo, n_out, out_pitch, out_origin);
    double q = fabs(out_pitch);
    /* each output cell overlaps at most ceil(q / in_pitch) + 1 input cells; the scan below
     * looks at one more on each side */
    double span = ceil(q / in_pitch) + 6;
    if (span > (double)POI_MAX_SIDE)
        return hv_error_set(HV_ERR_LIMIT, "POI: an output cell covers %.0f input cells", span);
    int maxn = (int)span;
    size_t cap = (size_t)n_out * (size_t)HV_MIN(maxn, 4);
    hv_status st = axis_alloc(ax, n_in, n_out, cap);
    if (st != HV_OK) return st;
    double *w = hv_malloc_array((size_t)maxn, sizeof *w);
    if (!w) {
        hv_poi_axis_free(ax);
        return HV_ERR_NOMEM;
    }
    for (int o = 0; o < n_out && st == HV_OK; ++o) {
        double a = out_origin + (double)o * out_pitch, b = a + out_pitch;
        double lo = HV_MIN(a, b), hi = HV_MAX(a, b);
        double f0 = floor((lo - in_lo) / in_pitch) - 1, f1 = ceil((hi - in_lo) / in_pitch) + 1;
        int i0 = (int)HV_CLAMP(f0, 0.0, (double)(n_in - 1));
        int i1 = (int)HV_CLAMP(f1, 0.0, (double)(n_in - 1));
        double total = 0;
        for (int i = i0; i <= i1; ++i) {
            double e0 = in_lo + (double)i * in_pitch, e1 = in_lo + (double)(i + 1) * in_pitch;
            double ov = HV_MIN(e1, hi) - HV_MAX(e0, lo);
            w[i - i0] = ov > 0 ? ov : 0;
            total += w[i - i0];
        }
        if (total > 0) {
            for (int i = i0; i <= i1; ++i) w[i - i0] /= total;
            st = axis_push(ax, &cap, o, i0, w, i1 - i0 + 1);
        } else {
            /* outside the input: the nearest input cell */
            double mid = 0.5 * (lo + hi);
            double fi = floor((mid - in_lo) / in_pitch);
            int i = (int)HV_CLAMP(fi, 0.0, (double)(n_in - 1));
            double one = 1.0;
            st = axis_push(ax, &cap, o, i, &one, 1);
        }
    }
    free(w);
    if (st != HV_OK) hv_poi_axis_free(ax);
    else ax->steps = 1;
    return st;
}

hv_status hv_poi_axis_compose(const hv_poi_axis *b, const hv_poi_axis *a, hv_poi_axis *c)
{
    memset(c, 0, sizeof *c);
    if (b->n_in != a->n_out)
        return hv_error_set(HV_ERR_INTERNAL, "POI: composing %d -> %d with %d -> %d", a->n_in,
                            a->n_out, b->n_in, b->n_out);
    size_t cap = (size_t)b->n_out * 4;
    hv_status st = axis_alloc(c, a->n_in, b->n_out, cap);
    if (st != HV_OK) return st;
    double *row = NULL;
    size_t row_cap = 0;
    for (int o = 0; o < b->n_out && st == HV_OK; ++o) {
        int lo = a->n_in, hi = -1;
        for (int t = 0; t < b->len[o]; ++t) {
            int k = b->start[o] + t;
            lo = HV_MIN(lo, a->start[k]);
            hi = HV_MAX(hi, a->start[k] + a->len[k] - 1);
        }
        if (hi < lo) { /* cannot happen: every cell has a weight */
            st = hv_error_set(HV_ERR_INTERNAL, "POI: empty composed cell %d", o);
            break;
        }
        size_t n = (size_t)(hi - lo + 1);
        if (n > row_cap) {
            st = hv_grow((void **)&row, &row_cap, n, sizeof *row);
            if (st != HV_OK) break;
        }
        memset(row, 0, n * sizeof *row);
        for (int t = 0; t < b->len[o]; ++t) {
            int k = b->start[o] + t;
            double wb = b->w[b->off[o] + (size_t)t];
            const double *wa = a->w + a->off[k];
            for (int s = 0; s < a->len[k]; ++s) row[a->start[k] - lo + s] += wb * wa[s];
        }
        st = axis_push(c, &cap, o, lo, row, (int)n);
    }
    free(row);
    if (st != HV_OK) hv_poi_axis_free(c);
    else c->steps = a->steps + b->steps;
    return st;
}

hv_status hv_poi_axis_chain(double in_lo, double in_pitch, int n_in, double out_origin,
                            double out_pitch, int n_out, double max_ratio, hv_poi_axis *ax)
{
    memset(ax, 0, sizeof *ax);
    double ratio = in_pitch / fabs(out_pitch);
    int steps = 1;
    if (max_ratio > 1 && ratio > max_ratio) steps = (int)ceil(log(ratio) / log(max_ratio) - 1e-9);
    if (steps < 1) steps = 1;
    if (steps > 64) steps = 64;
    /* intermediate grids I1 .. I(steps-1) over the input extent, ratio^(k/steps) finer */
    double extent = in_pitch * (double)n_in;
    hv_poi_axis cur;
    memset(&cur, 0, sizeof cur);
    int have = 0, n_prev = n_in;
    double pitch_prev = in_pitch;
    for (int k = 1; k < steps; ++k) {
        double nk = round((double)n_in * pow(ratio, (double)k / steps));
        if (nk <= (double)n_prev) continue; /* too small a step to matter */
        if (nk > (double)POI_MAX_SIDE) return hv_error_set(HV_ERR_LIMIT,
                                 "resampling to the printer grid needs an intermediate image of %.0f pixels along "
                                 "an axis (at most %d)", nk, POI_MAX_SIDE);
        int n = (int)nk;
        double pitch = extent / n;
        hv_poi_axis st1, comp;
        hv_status st = hv_poi_axis_step(in_lo, pitch_prev, n_prev, in_lo, pitch, n, &st1);
        if (st != HV_OK) {
            hv_poi_axis_free(&cur);
            return st;
        }
        if (have) {
            st = hv_poi_axis_compose(&st1, &cur, &comp);
            hv_poi_axis_free(&st1);
            hv_poi_axis_free(&cur);
            if (st != HV_OK) return st;
            cur = comp;
        } else {
            cur = st1;
            have = 1;
        }
        n_prev = n;
        pitch_prev = pitch;
    }
    hv_poi_axis last;
    hv_status st = hv_poi_axis_step(in_lo, pitch_prev, n_prev, out_origin, out_pitch, n_out, &last);
    if (st != HV_OK) {
        hv_poi_axis_free(&cur);
        return st;
    }
    if (!have) {
        *ax = last;
        return HV_OK;
    }
    st = hv_poi_axis_compose(&last, &cur, ax);
    hv_poi_axis_free(&last);
    hv_poi_axis_free(&cur);
    return st;
}

void hv_poi_apply(const hv_poi_axis *ax, const hv_poi_axis *ay, const float *src, float *dst,
                  double *tmp)
{
    int sw = ax->n_in, sh = ay->n_in, dw = ax->n_out, dh = ay->n_out;
    for (int j = 0; j < sh; ++j) {
        const float *s = src + (size_t)j * (size_t)sw;
        double *t = tmp + (size_t)j * (size_t)dw;
        for (int x = 0; x < dw; ++x) {
            const double *w = ax->w + ax->off[x];
            const float *p = s + ax->start[x];
            double acc = 0;
            for (int k = 0; k < ax->len[x]; ++k) acc += w[k] * (double)p[k];
            t[x] = acc;
        }
    }
    for (int y = 0; y < dh; ++y) {
        float *d = dst + (size_t)y * (size_t)dw;
        const double *w = ay->w + ay->off[y];
        for (int x = 0; x < dw; ++x) {
            double acc = 0;
            for (int k = 0; k < ay->len[y]; ++k)
                acc += w[k] * tmp[(size_t)(ay->start[y] + k) * (size_t)dw + (size_t)x];
            d[x] = (float)acc;
        }
    }
}

static hv_status check_sizes(const float *src, int sw, int sh, const float *dst, int dw, int dh)
{
    if (!src || !dst) return hv_error_set(HV_ERR_INVALID, "POI: NULL image");
    if (sw < 1 || sh < 1 || dw < 1 || dh < 1 || sw > POI_MAX_SIDE || sh > POI_MAX_SIDE ||
        dw > POI_MAX_SIDE || dh > POI_MAX_SIDE)
        return hv_error_set(HV_ERR_INVALID, "POI: image sizes %d x %d -> %d x %d (1 to %d a side)",
                            sw, sh, dw, dh, POI_MAX_SIDE);
    return HV_OK;
}

/* Both images cover [0, sw*dw] x [0, sh*dh]: the old pixel is dw (dh) units wide, the new one
 * sw (sh), so every overlap is an integer and Wu's coefficients come out exactly rounded. */
static hv_status resample(const float *src, int sw, int sh, float *dst, int dw, int dh,
                          double max_ratio)
{
    hv_status st = check_sizes(src, sw, sh, dst, dw, dh);
    if (st != HV_OK) return st;
    hv_poi_axis ax, ay;
    st = hv_poi_axis_chain(0, (double)dw, sw, 0, (double)sw, dw, max_ratio, &ax);
    if (st != HV_OK) return st;
    st = hv_poi_axis_chain(0, (double)dh, sh, 0, (double)sh, dh, max_ratio, &ay);
    if (st != HV_OK) {
        hv_poi_axis_free(&ax);
        return st;
    }
    double *tmp = hv_malloc_array((size_t)sh * (size_t)dw, sizeof *tmp);
    if (tmp) hv_poi_apply(&ax, &ay, src, dst, tmp);
    else st = HV_ERR_NOMEM;
    free(tmp);
    hv_poi_axis_free(&ax);
    hv_poi_axis_free(&ay);
    return st;
}

hv_status hv_poi_resample(const float *src, int sw, int sh, float *dst, int dw, int dh)
{
    return resample(src, sw, sh, dst, dw, dh, 0);
}

hv_status hv_poi_resample_steps(const float *src, int sw, int sh, float *dst, int dw, int dh,
                                double max_ratio)
{
    if (!isfinite(max_ratio)) return hv_error_set(HV_ERR_INVALID, "POI: step ratio %g is not finite", max_ratio);
    return resample(src, sw, sh, dst, dw, dh, max_ratio);
}
