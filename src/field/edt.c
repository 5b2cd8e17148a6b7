/* src/field/edt.c - exact Euclidean distance transform of a voxel mask, after Felzenszwalb &
 * Huttenlocher, "Distance Transforms of Sampled Functions" (Theory of Computing 2012), sec. 3
 * (1-D lower envelope of parabolas) and sec. 4 (separable extension to 3-D). */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "core/internal.h"
#include "field_internal.h"

/* Columns transformed together in the strided (y and x) passes: a tile of TILE adjacent rows
 * is gathered into a contiguous scratch buffer, so each memory line fetched serves TILE rows
 * (64 bytes = one cache line of floats at TILE 16, two at 32). */
#define TILE 32

typedef struct edt_scratch {
    float *tile;   /* TILE * n floats, sample q of row b at [b * n + q] */
    double *v;     /* envelope: positions of the parabolas */
    double *h;     /* envelope: f/s^2 + q^2 of each parabola (index units) */
    double *fv;    /* envelope: f of each parabola (physical units) */
    double *num;   /* envelope: left end of parabola k's interval is num[k] / den[k] */
    double *den;
    int64_t *mark; /* fill: parabola starting at each sample, else 0 (n + 1, kept zeroed) */
} edt_scratch;

typedef struct edt_ctx {
    const uint8_t *feature;
    float *out;
    int64_t nx, ny, nz;
    double s2[3];     /* squared spacing per axis */
    float *sqz;       /* sqz[d] = (d * sz)^2 for d in [0, nz] */
    edt_scratch *scr; /* one per thread */
    int64_t nkt;      /* tiles of TILE columns along z */
    float less;       /* the last pass writes max(distance - less, 0) */
} edt_ctx;

/* ---- scanning helpers: 16 bytes at a time where SSE2 is available (all x86-64) ---------- */

/* First index in [k, n) whose float is zero (== 0) or, with want_zero 0, nonzero; n if none. */
static int64_t scan_float(const float *r, int64_t k, int64_t n, int want_zero)
{
#ifdef __SSE2__
    const __m128 zero = _mm_setzero_ps();
    for (; k + 4 <= n; k += 4) {
        int m = _mm_movemask_ps(_mm_cmpeq_ps(_mm_loadu_ps(r + k), zero));
        if (!want_zero) m ^= 15;
        if (m) return k + __builtin_ctz((unsigned)m);
    }
#endif
    for (; k < n; ++k)
        if ((r[k] == 0.0f) == want_zero) return k;
    return n;
}

/* First index in [k, n) whose byte is nonzero (want_set) or zero (!want_set); n if none. */
static int64_t scan_byte(const uint8_t *f, int64_t k, int64_t n, int want_set)
{
#ifdef __SSE2__
    const __m128i zero = _mm_setzero_si128();
    for (; k + 16 <= n; k += 16) {
        int m = _mm_movemask_epi8(_mm_cmpeq_epi8(_mm_loadu_si128((const __m128i *)(f + k)), zero));
        if (want_set) m ^= 0xffff;
        if (m) return k + __builtin_ctz((unsigned)m);
    }
#endif
    for (; k < n; ++k)
        if ((f[k] != 0) == want_set) return k;
    return n;
}

/* min(max(x, lo), hi) without branches (maxsd/minsd): these clamps see unpredictable data. */
static inline double clamp_d(double x, double lo, double hi)
{
#ifdef __SSE2__
    return _mm_cvtsd_f64(_mm_min_sd(_mm_max_sd(_mm_set_sd(x), _mm_set_sd(lo)), _mm_set_sd(hi)));
#else
    return x < lo ? lo : x > hi ? hi : x;
#endif
}

/* Lower envelope (FH sec. 3) of the parabolas rooted at the finite samples of row[lo, e),
 * plus zero-valued barriers at lo - 1 and e when `left` / `right`, written back to row[lo, e).
 * The envelope is the lower convex hull of the points (q, f/s2 + q^2) in index units. Tuned
 * for branch-poor code: each parabola keeps its intersection with its predecessor as
 * num/den (den > 0), so the pop test is two multiplies, and a sentinel (den 0, num -1) stops
 * the pops at the bottom; the fill finds each sample's parabola by a running maximum over
 * parabola indices marked at their first sample, instead of a search loop. */
static void segment(float *row, int64_t lo, int64_t e, int left, int right, double s2,
                    edt_scratch *w)
{
    double *v = w->v, *h = w->h, *fv = w->fv, *num = w->num, *den = w->den;
    int64_t *mark = w->mark;
    const double inv = 1.0 / s2;
    int64_t k = -1;
    if (left) {
        double d = (double)(lo - 1);
        k = 0;
        v[0] = d;
        h[0] = d * d;
        fv[0] = 0;
        num[0] = -1.0; /* sentinel: the bottom parabola is never popped */
        den[0] = 0.0;
    }
    for (int64_t q = lo; q <= e; ++q) {
        float fq;
        if (q < e) {
            fq = row[q];
            if (fq == INFINITY) continue;
        } else {
            if (!right) break;
            fq = 0.0f;
        }
        double dq = (double)q, hq = (double)fq * inv + dq * dq;
        if (k >= 0) {
            double a, b;
            for (;;) { /* pop while q's intersection with v[k] is left of v[k]'s own */
                a = hq - h[k];
                b = 2.0 * (dq - v[k]);
                if (a * den[k] > num[k] * b) break;
                --k;
            }
            ++k;
            num[k] = a;
            den[k] = b;
        } else {
            k = 0;
            num[0] = -1.0;
            den[0] = 0.0;
        }
        v[k] = dq;
        h[k] = hq;
        fv[k] = fq;
    }
    if (k < 0) return; /* no finite sample and no barrier: stays INFINITY */
    /* Parabola j > 0 owns the samples right of its intersection with j - 1; mark its first
     * one (later, empty intervals starting at the same sample are overwritten in order). */
    int64_t cur = lo;
    const double span = (double)(e - lo), off = 1.0 - (double)lo;
    for (int64_t j = 1; j <= k; ++j) {
        int64_t start = lo + (int64_t)clamp_d(num[j] / den[j] + off, 0.0, span);
        cur = start > cur ? start : cur; /* monotone despite rounding */
        mark[cur] = j;
    }
    int64_t j = 0;
    for (int64_t p = lo; p < e; ++p) {
        int64_t t = mark[p];
        mark[p] = 0;
        j = t > j ? t : j;
        double d = (double)p - v[j];
        row[p] = (float)(fv[j] + s2 * d * d);
    }
    mark[e] = 0;
}

/* One 1-D transform (FH sec. 3, algorithm DT(f)) of the n contiguous samples of row with
 * squared spacing s2, in place, squared distances in and out.
 * Samples at INFINITY (no feature seen yet) add no parabola. A zero sample is a barrier: its
 * parabola lies below every parabola rooted beyond it on the samples before it, so the row
 * splits at zeros into independent segments, and zeros themselves are never rewritten. */
static void fh_row(float *row, int64_t n, double s2, edt_scratch *w)
{
    int64_t q = 0;
    while (q < n) {
        int64_t lo = scan_float(row, q, n, 0);
        if (lo == n) break;
        int64_t e = scan_float(row, lo + 1, n, 1);
        segment(row, lo, e, lo > 0, e < n, s2, w);
        q = e + 1;
    }
}

/* z pass of one row: the 1-D distance to the nearest feature along z is exact by two-sided
 * scanning (no envelope needed for a binary input). Runs are found 16 voxels at a time; the
 * squares are copied from the table (forward from the previous feature, backward from the
 * next), so the row costs about a memcpy. */
static void z_row(const edt_ctx *c, int64_t row)
{
    const uint8_t *f = c->feature + (size_t)row * (size_t)c->nz;
    float *o = c->out + (size_t)row * (size_t)c->nz;
    const float *sq = c->sqz;
    int64_t n = c->nz, prev = -1, k = 0;
    while (k < n) {
        int64_t nf = scan_byte(f, k, n, 1); /* next feature */
        if (prev < 0 && nf == n) {          /* no feature in the row */
            for (int64_t q = k; q < n; ++q) o[q] = INFINITY;
            break;
        }
        int64_t mid = nf; /* [k, mid) is nearer prev, [mid, nf) nearer nf */
        if (prev < 0)
            mid = k;
        else if (nf < n)
            mid = prev + (nf - prev) / 2 + 1; /* ties go to prev: equal distances anyway */
        memcpy(o + k, sq + (k - prev), (size_t)(mid - k) * sizeof(float));
        for (int64_t q = mid; q < nf; ++q) o[q] = sq[nf - q];
        if (nf == n) break;
        int64_t e = scan_byte(f, nf + 1, n, 0); /* end of the feature run */
        memset(o + nf, 0, (size_t)(e - nf) * sizeof(float));
        prev = e - 1;
        k = e;
    }
}

/* Gathers rows [0, n) x columns [0, bw) of a strided block (row r at base + r * pitch) into
 * the tile as bw contiguous rows of n samples (a transpose, by 4x4 blocks where SSE is
 * available), and back (taking square roots in the last pass). Rows of the x pass lie a whole
 * slice apart, beyond the reach of the hardware prefetchers, so the scatter of one tile
 * prefetches the lines of the next tile (`next`): the gather then finds them in cache. */
static void gather(float *tile, const float *base, size_t pitch, int64_t n, int64_t bw)
{
    size_t sn = (size_t)n;
    int64_t r = 0;
#ifdef __SSE2__
    if (bw == TILE)
        for (; r + 4 <= n; r += 4) {
            const float *s0 = base + (size_t)r * pitch;
            for (int b = 0; b < TILE; b += 4) {
                __m128 a0 = _mm_loadu_ps(s0 + b), a1 = _mm_loadu_ps(s0 + pitch + b),
                       a2 = _mm_loadu_ps(s0 + 2 * pitch + b), a3 = _mm_loadu_ps(s0 + 3 * pitch + b);
                _MM_TRANSPOSE4_PS(a0, a1, a2, a3);
                float *d = tile + (size_t)b * sn + (size_t)r;
                _mm_storeu_ps(d, a0);
                _mm_storeu_ps(d + sn, a1);
                _mm_storeu_ps(d + 2 * sn, a2);
                _mm_storeu_ps(d + 3 * sn, a3);
            }
        }
#endif
    for (; r < n; ++r)
        for (int64_t b = 0; b < bw; ++b)
            tile[(size_t)b * sn + (size_t)r] = base[(size_t)r * pitch + (size_t)b];
}

/* root: the last pass, writing max(sqrt(v) - less, 0) (less >= 0, so sqrt(v) where less = 0) */
static void scatter(const float *tile, float *base, size_t pitch, int64_t n, int64_t bw, int root,
                    int next, float less)
{
    size_t sn = (size_t)n;
    int64_t r = 0;
#ifdef __SSE2__
    if (bw == TILE)
        for (; r + 4 <= n; r += 4) {
            float *d0 = base + (size_t)r * pitch;
            if (next) /* the next tile's columns of these rows: same pages, lines not yet read */
                for (int q = 0; q < 4; ++q)
                    for (int l = 0; l < TILE; l += 16)
                        _mm_prefetch((const char *)(d0 + (size_t)q * pitch + TILE + l), _MM_HINT_T0);
            for (int b = 0; b < TILE; b += 4) {
                const float *s = tile + (size_t)b * sn + (size_t)r;
                __m128 a0 = _mm_loadu_ps(s), a1 = _mm_loadu_ps(s + sn),
                       a2 = _mm_loadu_ps(s + 2 * sn), a3 = _mm_loadu_ps(s + 3 * sn);
                _MM_TRANSPOSE4_PS(a0, a1, a2, a3);
                if (root) {
                    const __m128 l = _mm_set1_ps(less), z = _mm_setzero_ps();
                    a0 = _mm_max_ps(_mm_sub_ps(_mm_sqrt_ps(a0), l), z);
                    a1 = _mm_max_ps(_mm_sub_ps(_mm_sqrt_ps(a1), l), z);
                    a2 = _mm_max_ps(_mm_sub_ps(_mm_sqrt_ps(a2), l), z);
                    a3 = _mm_max_ps(_mm_sub_ps(_mm_sqrt_ps(a3), l), z);
                }
                _mm_storeu_ps(d0 + b, a0);
                _mm_storeu_ps(d0 + pitch + b, a1);
                _mm_storeu_ps(d0 + 2 * pitch + b, a2);
                _mm_storeu_ps(d0 + 3 * pitch + b, a3);
            }
        }
#endif
    for (; r < n; ++r)
        for (int64_t b = 0; b < bw; ++b) {
            float val = tile[(size_t)b * sn + (size_t)r];
            base[(size_t)r * pitch + (size_t)b] = root ? HV_MAX(sqrtf(val) - less, 0.0f) : val;
        }
}

/* y pass over tile t (columns TILE*t ...) of slice i: gather, transform, scatter. */
static void y_tile(const edt_ctx *c, int64_t i, int64_t t, edt_scratch *w)
{
    int64_t ny = c->ny, nz = c->nz, k0 = t * TILE;
    int64_t bw = HV_MIN((int64_t)TILE, nz - k0);
    float *base = c->out + ((size_t)i * (size_t)ny) * (size_t)nz + (size_t)k0;
    gather(w->tile, base, (size_t)nz, ny, bw);
    for (int64_t b = 0; b < bw; ++b) fh_row(w->tile + (size_t)b * (size_t)ny, ny, c->s2[1], w);
    scatter(w->tile, base, (size_t)nz, ny, bw, 0, t + 1 < c->nkt, 0);
}

/* x pass (the last) over tile t of the y-row j: rows are nx voxels one slice apart. */
static void x_tile(const edt_ctx *c, int64_t j, int64_t t, edt_scratch *w)
{
    int64_t nx = c->nx, nz = c->nz, k0 = t * TILE;
    size_t slice = (size_t)c->ny * (size_t)nz;
    int64_t bw = HV_MIN((int64_t)TILE, nz - k0);
    float *base = c->out + (size_t)j * (size_t)nz + (size_t)k0;
    gather(w->tile, base, slice, nx, bw);
    for (int64_t b = 0; b < bw; ++b) fh_row(w->tile + (size_t)b * (size_t)nx, nx, c->s2[0], w);
    scatter(w->tile, base, slice, nx, bw, 1, t + 1 < c->nkt, c->less); /* last pass: distances */
}

/* Slices i in [b, e): z pass of every row, then the y pass while the slice is in cache. */
static hv_status zy_slices(void *ctx, size_t b, size_t e, int thread)
{
    const edt_ctx *c = ctx;
    edt_scratch *w = &c->scr[thread];
    for (size_t i = b; i < e; ++i) {
        for (int64_t j = 0; j < c->ny; ++j) z_row(c, (int64_t)i * c->ny + j);
        if (c->ny > 1)
            for (int64_t t = 0; t < c->nkt; ++t) y_tile(c, (int64_t)i, t, w);
    }
    return HV_OK;
}

/* Unfused variants for grids with too few slices to keep every thread busy. */
static hv_status z_rows(void *ctx, size_t b, size_t e, int thread)
{
    (void)thread;
    for (size_t r = b; r < e; ++r) z_row(ctx, (int64_t)r);
    return HV_OK;
}

static hv_status y_tiles(void *ctx, size_t b, size_t e, int thread)
{
    const edt_ctx *c = ctx;
    for (size_t it = b; it < e; ++it)
        y_tile(c, (int64_t)it / c->nkt, (int64_t)it % c->nkt, &c->scr[thread]);
    return HV_OK;
}

static hv_status x_tiles(void *ctx, size_t b, size_t e, int thread)
{
    const edt_ctx *c = ctx;
    for (size_t it = b; it < e; ++it)
        x_tile(c, (int64_t)it / c->nkt, (int64_t)it % c->nkt, &c->scr[thread]);
    return HV_OK;
}

/* Grain for n items: about 32 chunks per thread (small enough that a thread descheduled on
 * a busy machine delays the pass by little), at least `min` items each. */
static size_t grain_for(size_t n, size_t min, int threads)
{
    size_t g = n / ((size_t)threads * 32);
    return HV_MAX(g, HV_MAX(min, (size_t)1));
}

hv_status hv_edt(const uint8_t *feature, const int64_t dims[3], const double spacing[3],
                 float *out, const hv_progress *progress)
{
    return hv_edt_less(feature, dims, spacing, 0.0f, out, progress);
}

hv_status hv_edt_less(const uint8_t *feature, const int64_t dims[3], const double spacing[3], float less,
                      float *out, const hv_progress *progress)
{
    if (!feature || !dims || !spacing || !out)
        return hv_error_set(HV_ERR_INVALID, "edt: %s is NULL",
                            !feature ? "feature" : !dims ? "dims" : !spacing ? "spacing" : "out");
    static const char axis[3] = {'x', 'y', 'z'};
    for (int a = 0; a < 3; ++a) {
        if (dims[a] < 1)
            return hv_error_set(HV_ERR_INVALID, "edt: dimension %c must be >= 1 (got %lld)",
                                axis[a], (long long)dims[a]);
        if (!(isfinite(spacing[a]) && spacing[a] > 0))
            return hv_error_set(HV_ERR_INVALID, "edt: spacing %c must be finite and > 0 (got %g)",
                                axis[a], spacing[a]);
    }
    const int64_t limit = (int64_t)1 << 40;
    if (dims[0] > limit || dims[1] > limit / dims[0] || dims[2] > limit / (dims[0] * dims[1]))
        return hv_error_set(HV_ERR_LIMIT, "edt: %lld x %lld x %lld voxels exceed the limit of 2^40",
                            (long long)dims[0], (long long)dims[1], (long long)dims[2]);
    /* squared distances live in floats between passes: each step must be a normal float and
     * the grid's diagonal must not overflow */
    double diag2 = 0;
    for (int a = 0; a < 3; ++a) {
        double ext = (double)dims[a] * spacing[a];
        diag2 += ext * ext;
        if (spacing[a] * spacing[a] < FLT_MIN)
            return hv_error_set(HV_ERR_INVALID,
                                "edt: spacing %c too small for float squared distances (got %g)",
                                axis[a], spacing[a]);
    }
    if (!(diag2 < FLT_MAX))
        return hv_error_set(HV_ERR_INVALID,
                            "edt: grid too large in physical units for float squared distances "
                            "(diagonal %g)",
                            sqrt(diag2));

    if (!(less >= 0 && isfinite(less))) return hv_error_set(HV_ERR_INVALID, "edt: offset %g (finite, >= 0)", (double)less);
    edt_ctx c = {feature, out, dims[0], dims[1], dims[2], {0, 0, 0}, NULL, NULL, 0, less};
    for (int a = 0; a < 3; ++a) c.s2[a] = spacing[a] * spacing[a];
    c.nkt = (c.nz + TILE - 1) / TILE;
    int threads = hv_threads();
    size_t n = (size_t)HV_MAX(c.nx, HV_MAX(c.ny, c.nz));
    hv_status s = HV_ERR_NOMEM;
    c.sqz = hv_malloc_array((size_t)c.nz + 1, sizeof(float));
    c.scr = hv_calloc((size_t)threads, sizeof(edt_scratch));
    if (!c.sqz || !c.scr) goto done;
    for (int t = 0; t < threads; ++t) {
        edt_scratch *w = &c.scr[t];
        w->tile = hv_malloc_array(n, TILE * sizeof(float));
        w->v = hv_malloc_array(n + 2, sizeof(double));
        w->h = hv_malloc_array(n + 2, sizeof(double));
        w->fv = hv_malloc_array(n + 2, sizeof(double));
        w->num = hv_malloc_array(n + 2, sizeof(double));
        w->den = hv_malloc_array(n + 2, sizeof(double));
        w->mark = hv_calloc(n + 1, sizeof(int64_t));
        if (!w->tile || !w->v || !w->h || !w->fv || !w->num || !w->den || !w->mark) goto done;
    }
    for (int64_t d = 0; d <= c.nz; ++d) {
        double len = (double)d * spacing[2];
        c.sqz[d] = (float)(len * len);
    }

    size_t nx = (size_t)c.nx, ny = (size_t)c.ny;
    if (nx >= (size_t)threads * 4) {
        s = hv_parallel_for(nx, grain_for(nx, 1, threads), zy_slices, &c, progress, "edt: z+y");
    } else {
        s = hv_parallel_for(nx * ny, grain_for(nx * ny, 64, threads), z_rows, &c, progress,
                            "edt: z");
        if (s == HV_OK && ny > 1) {
            size_t items = nx * (size_t)c.nkt;
            s = hv_parallel_for(items, grain_for(items, 1, threads), y_tiles, &c, progress,
                                "edt: y");
        }
    }
    if (s == HV_OK) {
        size_t items = ny * (size_t)c.nkt;
        s = hv_parallel_for(items, grain_for(items, 1, threads), x_tiles, &c, progress, "edt: x");
    }

done:
    if (c.scr)
        for (int t = 0; t < threads; ++t) {
            free(c.scr[t].tile);
            free(c.scr[t].v);
            free(c.scr[t].h);
            free(c.scr[t].fv);
            free(c.scr[t].num);
            free(c.scr[t].den);
            free(c.scr[t].mark);
        }
    free(c.scr);
    free(c.sqz);
    return s;
}
