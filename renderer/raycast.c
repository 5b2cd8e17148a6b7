/* renderer/raycast.c - the modified ray-casting pipeline of Wu 2.3: per sample, trilinear
 * material composition -> colour sum p_j * colour_j, opacity from the trilinear occupancy through
 * a transfer function, gradient shading with a key light, front-to-back compositing with early
 * ray termination; empty blocks are stepped over with a two-level 3D DDA (Amanatides-Woo 1987)
 * on the scene's block table. Surface mode finds the first crossing of the occupancy level and
 * refines it by bisection. Clips remove convex regions; their faces show the composition. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "core/internal.h"
#include "render_internal.h"

#define TILE 32 /* tile edge in pixels; smaller for small images, so every thread has work */
#define T_MIN (1.0f / 512.0f) /* early termination: the rest is below 8-bit resolution */
#define BISECT_STEPS 8
/* Sample opacity 1 - exp(-k u), u = ramp * alpha_mix in [0, 1], from a table with linear
 * interpolation: error below k^2 / (8 N^2), under 1e-6 for k <= 2 (a sample that opaque
 * ends the ray anyway). */
#define OPACITY_N 1024

typedef float v4f __attribute__((vector_size(16)));
typedef uint8_t v4u8 __attribute__((vector_size(4)));

/* ---- per-render context ----------------------------------------------------------------- */

typedef struct cplane {
    double n[3]; /* unit normal */
    double off;  /* n . x > off is inside the removed region */
} cplane;

typedef struct rctx rctx;
struct ray;
typedef struct rctx {
    const hv_render_scene *s;
    const hv_render_options *o;
    rcam cam;
    hv_image *img;
    int tile, tiles_x, tiles_y;
    double dt, idt;     /* world step, its inverse (for guesses only) */
    int solid_cells;    /* a sample in a cell of solid corners composites as a solid brick's */
    void (*march)(const struct rctx *, struct ray *, const rvox *, const uint64_t *, int, int, const int32_t *,
                  double, double, double); /* march_brick for this machine */
    double box_lo[3], box_hi[3]; /* index box where the coverage can be > 0 */
    float density, tf_lo, tf_scale, iso;
    float ka, kd, ks, shin;
    float L[3];         /* unit, world, towards the light */
    float ivox[3];      /* 1 / voxel size */
    float opacity[OPACITY_N + 2]; /* 1 - exp(-density dt u) at u = i / OPACITY_N */
    float op_byte[256];           /* opacity_of(i / 255): of a material alpha byte */
    float bg[4];        /* premultiplied background */
    double foot[4];     /* rays through image positions outside this rectangle miss the box */
    int nclips;
    int nplanes[HV_RENDER_MAX_CLIPS];
    cplane planes[HV_RENDER_MAX_CLIPS][HV_CLIP_MAX_PLANES];
} rctx;

/* What a ray has gathered: premultiplied colour, transmittance, and whether it is complete. */
typedef struct racc {
    v4f C;   /* lanes 0-2 (lane 3 is scratch) */
    float T;
    int done;
} racc;

typedef struct ray ray;
typedef struct ray {
    double o[3], d[3];   /* world */
    double oi[3], di[3]; /* index space: p(t) = oi + t di */
    float H[3];          /* Blinn half vector */
    double tdelta8[3];   /* ray parameter across 8 index units along each axis (HUGE_VAL: never) */
    float dp[4];         /* index-space step between samples, dt di */
    racc a;
    int64_t next_n;      /* next sample index on the lattice t = n dt */
    float prev_cov;      /* surface mode: coverage at the previous sample */
    double prev_t;
} ray;

/* ---- sampling --------------------------------------------------------------------------- */

/* The eight bytes of a brick voxel as two float vectors: (r, g, b, a) and (occ, gx, gy, gz). */
static inline __attribute__((always_inline)) void expand(const rvox *v, v4f *col, v4f *og)
{
#if defined(__SSE2__)
    const __m128i zero = _mm_setzero_si128();
    __m128i w = _mm_unpacklo_epi8(_mm_loadl_epi64((const __m128i *)(const void *)v), zero);
    *col = (v4f)_mm_cvtepi32_ps(_mm_unpacklo_epi16(w, zero));
    *og = (v4f)_mm_cvtepi32_ps(_mm_unpackhi_epi16(w, zero));
#else
    v4u8 a, b;
    memcpy(&a, &v->r, 4);
    memcpy(&b, &v->occ, 4);
    *col = __builtin_convertvector(a, v4f);
    *og = __builtin_convertvector(b, v4f);
#endif
}

/* The colour bytes (r, g, b, a) of a brick voxel as a float vector: expand()'s first. */
static inline __attribute__((always_inline)) v4f expand_colour(const rvox *v)
{
#if defined(__SSE2__)
    const __m128i zero = _mm_setzero_si128();
    int32_t w;
    memcpy(&w, v, 4);
    __m128i x = _mm_unpacklo_epi8(_mm_cvtsi32_si128(w), zero);
    return (v4f)_mm_cvtepi32_ps(_mm_unpacklo_epi16(x, zero));
#else
    v4u8 a;
    memcpy(&a, &v->r, 4);
    return __builtin_convertvector(a, v4f);
#endif
}

static inline v4f lerp4(v4f a, v4f b, float t)
{
    return a + (b - a) * t;
}

static inline v4f trilerp(const v4f c[8], float fx, float fy, float fz)
{
    v4f c00 = lerp4(c[0], c[1], fz), c01 = lerp4(c[2], c[3], fz);
    v4f c10 = lerp4(c[4], c[5], fz), c11 = lerp4(c[6], c[7], fz);
    return lerp4(lerp4(c00, c01, fy), lerp4(c10, c11, fy), fx);
}

/* Trilinear interpolation at fractions f of the eight corners v + {0,1}^3: occupancy and
 * gradient vector *og, and (when col != NULL) the colour vector *col. */
/* The eight corners v + {0,1}^3, in trilerp order (x slowest). */
static inline __attribute__((always_inline)) void corners(const rvox *v, v4f lo[8], v4f hi[8])
{
    enum { DY = RB_DIM, DX = RB_DIM * RB_DIM };
    expand(v, &lo[0], &hi[0]);
    expand(v + 1, &lo[1], &hi[1]);
    expand(v + DY, &lo[2], &hi[2]);
    expand(v + DY + 1, &lo[3], &hi[3]);
    expand(v + DX, &lo[4], &hi[4]);
    expand(v + DX + 1, &lo[5], &hi[5]);
    expand(v + DX + DY, &lo[6], &hi[6]);
    expand(v + DX + DY + 1, &lo[7], &hi[7]);
}

static inline __attribute__((always_inline)) void tri8(const rvox *v, const float f[3], v4f *og,
                                                       v4f *col)
{
    v4f lo[8], hi[8];
    corners(v, lo, hi);
    *og = trilerp(hi, f[0], f[1], f[2]);
    if (col) *col = trilerp(lo, f[0], f[1], f[2]);
}

/* Local position of index point p in the brick of block b: integer corner and fractions,
 * clamped into the brick (a point a rounding error outside its block is moved onto its face). */
static inline const rvox *locate(const rvox *bk, const int32_t b[3], const double p[3], float f[3])
{
    int li[3];
    for (int a = 0; a < 3; ++a) {
        double l = p[a] - 8.0 * b[a];
        if (l < 0) l = 0;
        if (l > 8) l = 8;
        int i = (int)l;
        if (i > 7) i = 7;
        li[a] = i;
        f[a] = (float)(l - i);
    }
    return bk + RB_INDEX(li[0], li[1], li[2]);
}

/* Sample anywhere (index point p): occupancy/gradient vector and colour vector; returns 0
 * (vectors zero) where no brick exists. */
static int sample_point(const hv_render_scene *s, const double p[3], v4f *og, v4f *col)
{
    int32_t b[3];
    for (int a = 0; a < 3; ++a) {
        double fl = floor(p[a]);
        if (!(fl > -2e9 && fl < 2e9)) goto none;
        b[a] = r_floor_shift((int32_t)fl, 3);
    }
    const rvox *bk = r_brick(s, b[0], b[1], b[2]);
    if (!bk) goto none;
    float f[3];
    const rvox *v = locate(bk, b, p, f);
    tri8(v, f, og, col);
    return 1;
none:
    *og = (v4f){0, 128, 128, 128};
    if (col) *col = (v4f){0, 0, 0, 0};
    return 0;
}

static inline void ray_point(const ray *r, double t, double p[3])
{
    for (int a = 0; a < 3; ++a) p[a] = r->oi[a] + t * r->di[a];
}

/* ---- shading ---------------------------------------------------------------------------- */

/* colour * (ambient + diffuse max(0, n.l)) + specular (n.h)^k, blended with the plain colour by
 * w (the gradient strength; 1 for surfaces), clamped to [0, 1]. n: unit outward normal. */
static inline void shade(const rctx *c, const ray *r, const float col[3], const float n[3],
                         float w, float out[3])
{
    float nl = n[0] * c->L[0] + n[1] * c->L[1] + n[2] * c->L[2];
    float diff = nl > 0 ? nl : 0, spec = 0;
    if (nl > 0 && c->ks > 0) {
        float nh = n[0] * r->H[0] + n[1] * r->H[1] + n[2] * r->H[2];
        if (nh > 0) spec = c->ks * powf(nh, c->shin);
    }
    float k = c->ka + c->kd * diff;
    for (int i = 0; i < 3; ++i) {
        float lit = col[i] * k + spec;
        float v = col[i] + w * (lit - col[i]);
        out[i] = v < 0 ? 0 : v > 1 ? 1 : v;
    }
}

/* Outward unit normal from the (biased) gradient lanes of og, in world space; the gradient is
 * in index units, so divide by the voxel size per axis. Returns the gradient magnitude in the
 * stored units (a flat face of solid voxels: 127). */
static inline float normal_of(const rctx *c, v4f og, float n[3])
{
    float g[3] = {og[1] - 128.0f, og[2] - 128.0f, og[3] - 128.0f};
    float m = sqrtf(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    float w[3];
    for (int a = 0; a < 3; ++a) w[a] = -g[a] * c->ivox[a];
    float wl = sqrtf(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (wl > 0)
        for (int a = 0; a < 3; ++a) n[a] = w[a] / wl;
    else
        n[0] = n[1] = n[2] = 0;
    return m;
}

/* ---- compositing ------------------------------------------------------------------------ */

/* (the colour's lanes 0-2 count; lane for lane, the arithmetic of three scalar sums) */
static inline void composite_v(racc *r, v4f col, float alpha)
{
    float ta = r->T * alpha;
    r->C += ta * col;
    r->T -= ta;
    if (r->T < T_MIN) { /* the rest would not change an 8-bit pixel: absorb it here */
        r->C += r->T * col;
        r->T = 0;
        r->done = 1;
    }
}

static inline void composite(racc *r, const float col[3], float alpha)
{
    composite_v(r, (v4f){col[0], col[1], col[2], 0}, alpha);
}

/* Colour (straight) of the composition from the colour and occupancy vectors. */
static inline void colour_of(v4f og, v4f col, float out[3], float *amix)
{
    float inv = og[0] > 0 ? 1.0f / og[0] : 0;
    out[0] = col[0] * inv;
    out[1] = col[1] * inv;
    out[2] = col[2] * inv;
    if (amix) *amix = col[3] * inv;
}

/* A cut face at ray parameter t (world) with unit normal n facing the viewer. */
static void cut_face(const rctx *c, ray *r, double t, const double n[3])
{
    double p[3];
    ray_point(r, t, p);
    v4f og, col;
    if (!sample_point(c->s, p, &og, &col)) return;
    float cov = og[0] * (1.0f / 255.0f), alpha;
    if (c->o->mode == HV_RENDER_SURFACE) {
        if (cov < c->iso) return;
        alpha = (float)c->o->cut_opacity;
    } else { /* soft edge, so the face outline matches the soft volume silhouette */
        float e = (cov - (c->iso - 0.25f)) * 2.0f;
        e = e < 0 ? 0 : e > 1 ? 1 : e;
        alpha = (float)c->o->cut_opacity * e * e * (3 - 2 * e);
    }
    if (alpha <= 0) return;
    float rgb[3], nf[3] = {(float)n[0], (float)n[1], (float)n[2]}, out[3];
    colour_of(og, col, rgb, NULL);
    if (c->kd > 0) {
        /* a cut face is there to show the composition: lit from the eye (a headlight, no
         * highlight) on top of a raised ambient, so a face the key light misses stays
         * readable and faces at different angles still tell apart */
        float nv = -(nf[0] * (float)r->d[0] + nf[1] * (float)r->d[1] + nf[2] * (float)r->d[2]);
        float k = 0.6f + 0.4f * (nv < 0 ? -nv : nv);
        for (int i = 0; i < 3; ++i) out[i] = rgb[i] * k > 1 ? 1 : rgb[i] * k;
    } else {
        shade(c, r, rgb, nf, 1.0f, out);
    }
    composite(&r->a, out, alpha);
    if (c->o->mode == HV_RENDER_SURFACE && alpha >= 1) r->a.done = 1;
}

/* Surface mode: the crossing lies in (t0, t1] with cov(t0) < iso <= cov(t1). */
static void surface_hit(const rctx *c, ray *r, double t0, float c0, double t1, float c1)
{
    double p[3];
    v4f og, col;
    for (int i = 0; i < BISECT_STEPS; ++i) {
        double tm = 0.5 * (t0 + t1);
        ray_point(r, tm, p);
        sample_point(c->s, p, &og, NULL);
        float cm = og[0] * (1.0f / 255.0f);
        if (cm >= c->iso) {
            t1 = tm;
            c1 = cm;
        } else {
            t0 = tm;
            c0 = cm;
        }
    }
    double th = c1 > c0 ? t0 + (t1 - t0) * (double)((c->iso - c0) / (c1 - c0)) : t1;
    ray_point(r, th, p);
    if (!sample_point(c->s, p, &og, &col) || !(og[0] > 0)) {
        ray_point(r, t1, p); /* the interpolated point fell on an empty corner set */
        sample_point(c->s, p, &og, &col);
    }
    float rgb[3], n[3], out[3];
    colour_of(og, col, rgb, NULL);
    if (normal_of(c, og, n) < 2.0f)
        for (int a = 0; a < 3; ++a) n[a] = (float)-r->d[a];
    shade(c, r, rgb, n, 1.0f, out);
    composite(&r->a, out, 1.0f);
    r->a.done = 1;
}

/* Opacity of one sample for u = ramp(coverage) * alpha_mix in [0, 1], from the table. */
static inline float opacity_of(const rctx *c, float u01)
{
    float u = u01 * (float)OPACITY_N;
    if (!(u > 0)) return 0;
    int ui = (int)u;
    ui = ui > OPACITY_N ? OPACITY_N : ui;
    return c->opacity[ui] + (u - (float)ui) * (c->opacity[ui + 1] - c->opacity[ui]);
}

/* A volume sample inside a solid brick: the trilinear colour of the eight corners (all
 * occupied), full coverage, plain colour. */
static inline __attribute__((always_inline)) v4f solid_colour(const rvox *v, const float f[3])
{
    enum { DY = RB_DIM, DX = RB_DIM * RB_DIM };
    v4f lo[8] = {expand_colour(v),           expand_colour(v + 1),      expand_colour(v + DY),
                 expand_colour(v + DY + 1),  expand_colour(v + DX),     expand_colour(v + DX + 1),
                 expand_colour(v + DX + DY), expand_colour(v + DX + DY + 1)};
    return trilerp(lo, f[0], f[1], f[2]) * (1.0f / 255.0f);
}


/* The samples n, n+1, ... (t < tc1, t <= tend) of a uniform brick are all alike: k of them
 * leave T (1 - alpha)^k and add T c (1 - (1 - alpha)^k), what one by one compositing gives. */
static void composite_uniform(const rctx *c, ray *r, const rvox *bk, int64_t n, double tc1,
                              double tend)
{
    /* the last lattice point with t < tc1 and t <= tend, by the same test as march_brick */
    const double dt = c->dt;
    int64_t last = (int64_t)floor(HV_MIN(tc1, tend) / dt);
    while ((double)(last + 1) * dt < tc1 && (double)(last + 1) * dt <= tend) ++last;
    while (last >= n && !((double)last * dt < tc1 && (double)last * dt <= tend)) --last;
    int64_t k = last - n + 1;
    r->next_n = n + (k > 0 ? k : 0);
    if (k <= 0) return;
    float rgb[3] = {bk->r * (1.0f / 255.0f), bk->g * (1.0f / 255.0f), bk->b * (1.0f / 255.0f)};
    float alpha = opacity_of(c, bk->a * (1.0f / 255.0f));
    if (alpha > 0) composite(&r->a, rgb, alpha >= 1 ? 1 : 1 - powf(1 - alpha, (float)k));
}

/* The first lattice index m >= n with m dt >= tc1 or m dt > tend: the end of a brick's run of
 * samples, found from a guess by the very test a sample-by-sample loop would make. */
static inline int64_t run_end(const rctx *c, int64_t n, double tc1, double tend)
{
    const double dt = c->dt, lim = HV_MIN(tc1, tend);
    int64_t m = lim < (double)INT64_MAX / 2 * dt ? (int64_t)(lim * c->idt) : INT64_MAX / 2;
    if (m < n) m = n;
#define RUN_STOP(m) ((double)(m) * dt >= tc1 || (double)(m) * dt > tend)
    while (!RUN_STOP(m)) ++m;
    while (m > n && RUN_STOP(m - 1)) --m;
#undef RUN_STOP
    return m;
}

/* Local position of sample k of a run, p0 + k dp in the brick, clamped into it: the voxel
 * (RB_INDEX), the cell (HV_LEAF_OFFSET) and the fractions f. */
static inline __attribute__((always_inline)) void run_point(const float p0[4], const float dp[4], int k,
                                                            int *voxel, unsigned *cell, float f[3])
{
#if defined(__SSE2__)
    __m128 l = _mm_add_ps(_mm_loadu_ps(p0), _mm_mul_ps(_mm_set1_ps((float)k), _mm_loadu_ps(dp)));
    l = _mm_min_ps(_mm_max_ps(l, _mm_setzero_ps()), _mm_set1_ps(8.0f));
    __m128i i = _mm_cvttps_epi32(_mm_min_ps(l, _mm_set1_ps(7.0f)));
    __m128 fr = _mm_sub_ps(l, _mm_cvtepi32_ps(i));
    int32_t li[4];
    float ff[4];
    _mm_storeu_si128((__m128i *)(void *)li, i);
    _mm_storeu_ps(ff, fr);
    f[0] = ff[0];
    f[1] = ff[1];
    f[2] = ff[2];
#else
    int li[3];
    for (int a = 0; a < 3; ++a) {
        float l = p0[a] + (float)k * dp[a];
        l = l < 0 ? 0 : l > 8 ? 8 : l;
        int i = (int)l;
        i = i > 7 ? 7 : i;
        li[a] = i;
        f[a] = l - (float)i;
    }
#endif
    *voxel = RB_INDEX(li[0], li[1], li[2]);
    *cell = (unsigned)(li[0] << 6 | li[1] << 3 | li[2]);
}

/* The general variant, SSE2 (x86-64's baseline) or plain C. */
#define MB_NAME march_brick_base
#define MB_TARGET
#define MB_INTERP(v, f, og, col) tri8(v, f, og, col)
#define MB_SOLID_COLOUR(v, f) solid_colour(v, f)
#include "march_brick.inc"

#if defined(__x86_64__) && defined(__GNUC__)
/* The AVX2 variant: a voxel's eight bytes as one 8-float vector, the seven lerps of a trilinear
 * sample on both its colour and its occupancy/gradient at once. */
#define AVX2 __attribute__((target("avx2")))

static inline AVX2 __attribute__((always_inline)) __m256 lerp8(__m256 a, __m256 b, __m256 t)
{
    return _mm256_add_ps(a, _mm256_mul_ps(_mm256_sub_ps(b, a), t));
}

static inline AVX2 __attribute__((always_inline)) __m256 expand8(const rvox *v)
{
    return _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)(const void *)v)));
}

/* tri8: the lerps of trilerp() in its order, the colour in lanes 0-3, the rest in 4-7 */
static inline AVX2 __attribute__((always_inline)) void tri8_avx2(const rvox *v, const float f[3], v4f *og, v4f *col)
{
    enum { DY = RB_DIM, DX = RB_DIM * RB_DIM };
    const __m256 tx = _mm256_set1_ps(f[0]), ty = _mm256_set1_ps(f[1]), tz = _mm256_set1_ps(f[2]);
    __m256 c00 = lerp8(expand8(v), expand8(v + 1), tz), c01 = lerp8(expand8(v + DY), expand8(v + DY + 1), tz);
    __m256 c10 = lerp8(expand8(v + DX), expand8(v + DX + 1), tz);
    __m256 c11 = lerp8(expand8(v + DX + DY), expand8(v + DX + DY + 1), tz);
    __m256 x = lerp8(lerp8(c00, c01, ty), lerp8(c10, c11, ty), tx);
    *col = (v4f)_mm256_castps256_ps128(x);
    *og = (v4f)_mm256_extractf128_ps(x, 1);
}

/* The colours of two voxels a, b as one vector [a | b]. */
static inline AVX2 __attribute__((always_inline)) __m256 colour2(const rvox *a, const rvox *b)
{
    int32_t wa, wb;
    memcpy(&wa, a, 4);
    memcpy(&wb, b, 4);
    return _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_unpacklo_epi32(_mm_cvtsi32_si128(wa), _mm_cvtsi32_si128(wb))));
}

/* solid_colour: corners paired [0|2], [1|3], [4|6], [5|7], lerped along z, regrouped, along y,
 * then the halves along x */
static inline AVX2 __attribute__((always_inline)) v4f solid_colour_avx2(const rvox *v, const float f[3])
{
    enum { DY = RB_DIM, DX = RB_DIM * RB_DIM };
    const __m256 ty = _mm256_set1_ps(f[1]), tz = _mm256_set1_ps(f[2]);
    __m256 z0 = lerp8(colour2(v, v + DY), colour2(v + 1, v + DY + 1), tz);            /* [c00 | c01] */
    __m256 z1 = lerp8(colour2(v + DX, v + DX + DY), colour2(v + DX + 1, v + DX + DY + 1), tz); /* [c10 | c11] */
    __m256 y = lerp8(_mm256_permute2f128_ps(z0, z1, 0x20), _mm256_permute2f128_ps(z0, z1, 0x31), ty);
    v4f lo = (v4f)_mm256_castps256_ps128(y), hi = (v4f)_mm256_extractf128_ps(y, 1);
    return lerp4(lo, hi, f[0]) * (1.0f / 255.0f);
}

#define MB_NAME march_brick_avx2
#define MB_TARGET AVX2
#define MB_INTERP(v, f, og, col) tri8_avx2(v, f, og, col)
#define MB_SOLID_COLOUR(v, f) solid_colour_avx2(v, f)
#include "march_brick.inc"
#endif

/* The variant for this machine; r_render_base forces the general one (tests compare them). */
typedef void (*march_fn)(const rctx *, ray *, const rvox *, const uint64_t *, int, int, const int32_t *, double,
                         double, double);
int r_render_base;

static march_fn march_variant(void)
{
#if defined(__x86_64__) && defined(__GNUC__)
    if (!r_render_base && __builtin_cpu_supports("avx2")) return march_brick_avx2;
#endif
    return march_brick_base;
}

/* 3D DDA state over cells of `size` index units, cell coordinates within [lo, hi]. */
typedef struct dda {
    int32_t c[3], step[3], lo[3], hi[3];
    double tnext[3], tdelta[3];
} dda;

/* size: 8 or 64. Dividing by a power of two is multiplying by its exact inverse, and size / di
 * is (size / 8) (8 / di) exactly: the ray's tdelta8 scaled. */
static void dda_init(dda *g, const ray *r, double t, double size, const int32_t lo[3],
                     const int32_t hi[3])
{
    const double inv = 1.0 / size, scale = size * 0.125;
    for (int a = 0; a < 3; ++a) {
        g->lo[a] = lo[a];
        g->hi[a] = hi[a];
        double p = r->oi[a] + t * r->di[a];
        double cf = floor(p * inv);
        int32_t ci = cf < (double)lo[a] ? lo[a] : cf > (double)hi[a] ? hi[a] : (int32_t)cf;
        g->c[a] = ci;
        if (r->di[a] > 0) {
            g->step[a] = 1;
            g->tnext[a] = ((double)(ci + 1) * size - r->oi[a]) / r->di[a];
            g->tdelta[a] = scale * r->tdelta8[a];
        } else if (r->di[a] < 0) {
            g->step[a] = -1;
            g->tnext[a] = ((double)ci * size - r->oi[a]) / r->di[a];
            g->tdelta[a] = scale * r->tdelta8[a];
        } else {
            g->step[a] = 0;
            g->tnext[a] = HUGE_VAL;
            g->tdelta[a] = HUGE_VAL;
        }
    }
}

/* Advance to the next cell; returns 0 when leaving [lo, hi]. *t receives the entry parameter. */
static inline int dda_next(dda *g, double *t)
{
    int a = g->tnext[0] < g->tnext[1] ? (g->tnext[0] < g->tnext[2] ? 0 : 2)
                                      : (g->tnext[1] < g->tnext[2] ? 1 : 2);
    *t = g->tnext[a];
    g->c[a] += g->step[a];
    g->tnext[a] += g->tdelta[a];
    return g->c[a] >= g->lo[a] && g->c[a] <= g->hi[a];
}

static inline double dda_exit(const dda *g)
{
    return HV_MIN(g->tnext[0], HV_MIN(g->tnext[1], g->tnext[2]));
}

/* March [ta, tb]: macro cells of 64^3 voxels, then blocks of 8^3 inside occupied macros. */
static void march(const rctx *c, ray *r, double ta, double tb)
{
    const hv_render_scene *s = c->s;
    int32_t mlo[3], mhi[3];
    for (int a = 0; a < 3; ++a) {
        mlo[a] = s->mlo[a];
        mhi[a] = s->mlo[a] + s->mdims[a] - 1;
    }
    dda M;
    dda_init(&M, r, ta, 64.0, mlo, mhi);
    double t = ta;
    while (t <= tb && !r->a.done) {
        double mt1 = HV_MIN(dda_exit(&M), tb);
        int32_t m[3] = {M.c[0] - s->mlo[0], M.c[1] - s->mlo[1], M.c[2] - s->mlo[2]};
        int32_t pg = s->top[((int64_t)m[0] * s->mdims[1] + m[1]) * s->mdims[2] + m[2]];
        if (pg >= 0 && mt1 >= t) {
            const rpage *page = &s->pages[pg];
            int32_t blo[3], bhi[3];
            for (int a = 0; a < 3; ++a) {
                blo[a] = M.c[a] * 8;
                bhi[a] = blo[a] + 7;
            }
            dda B;
            dda_init(&B, r, t, 8.0, blo, bhi);
            double bt = t;
            for (;;) {
                double bt1 = HV_MIN(dda_exit(&B), mt1);
                int32_t bi = page->brick[RP_INDEX(B.c[0], B.c[1], B.c[2])];
                if (bi >= 0 && bt1 >= bt) {
                    double cell_end = bt1 >= tb ? HUGE_VAL : bt1; /* the last cell includes tb */
                    size_t slot = r_brick_slot(s, bi);
                    c->march(c, r, s->bricks + slot * RB_VOX, s->cells + slot * RC_WORDS, s->brick_kind[bi],
                             s->brick_alpha[bi], B.c, bt, cell_end, tb);
                    if (r->a.done) return;
                }
                if (bt1 >= mt1 || !dda_next(&B, &bt)) break;
            }
        }
        if (mt1 >= tb || !dda_next(&M, &t)) break;
    }
}

/* ---- clips ------------------------------------------------------------------------------ */

typedef struct span {
    double t0, t1;
    int clip, plane; /* the plane through which the ray leaves the removed region at t1 */
} span;

static int span_cmp(const void *a, const void *b)
{
    const span *x = a, *y = b;
    return x->t0 < y->t0 ? -1 : x->t0 > y->t0;
}

/* Kept intervals of [tmin, tmax] after removing the clip regions; cut[i] >= 0 names the
 * (clip*HV_CLIP_MAX_PLANES + plane) whose face starts interval i. Returns the count. */
static int kept_intervals(const rctx *c, const ray *r, double tmin, double tmax,
                          double (*iv)[2], int *cut)
{
    span sp[HV_RENDER_MAX_CLIPS];
    int ns = 0;
    for (int k = 0; k < c->nclips; ++k) {
        double lo = -HUGE_VAL, hi = HUGE_VAL;
        int hip = -1, empty = 0;
        for (int p = 0; p < c->nplanes[k]; ++p) {
            const cplane *pl = &c->planes[k][p];
            double nd = pl->n[0] * r->d[0] + pl->n[1] * r->d[1] + pl->n[2] * r->d[2];
            double no = pl->n[0] * r->o[0] + pl->n[1] * r->o[1] + pl->n[2] * r->o[2];
            if (nd == 0) {
                if (!(no > pl->off)) empty = 1;
                continue;
            }
            double th = (pl->off - no) / nd;
            if (nd > 0) {
                if (th > lo) lo = th;
            } else if (th < hi) {
                hi = th;
                hip = p;
            }
        }
        if (empty || !(lo < hi) || hi < tmin || lo > tmax) continue;
        sp[ns].t0 = lo;
        sp[ns].t1 = hi;
        sp[ns].clip = k;
        sp[ns].plane = hip;
        ++ns;
    }
    if (ns > 1) qsort(sp, (size_t)ns, sizeof *sp, span_cmp);
    int n = 0;
    double t = tmin;
    int tcut = -1;
    for (int i = 0; i < ns;) {
        /* merge overlapping removed spans */
        double a = sp[i].t0, b = sp[i].t1;
        int bc = sp[i].plane >= 0 ? sp[i].clip * HV_CLIP_MAX_PLANES + sp[i].plane : -1;
        for (++i; i < ns && sp[i].t0 <= b; ++i)
            if (sp[i].t1 > b) {
                b = sp[i].t1;
                bc = sp[i].plane >= 0 ? sp[i].clip * HV_CLIP_MAX_PLANES + sp[i].plane : -1;
            }
        if (a > t) {
            iv[n][0] = t;
            iv[n][1] = HV_MIN(a, tmax);
            cut[n++] = tcut;
        }
        if (b >= tmax) return n;
        if (b > t) {
            t = b;
            tcut = bc;
        }
    }
    if (t <= tmax) {
        iv[n][0] = t;
        iv[n][1] = tmax;
        cut[n++] = tcut;
    }
    return n;
}

/* ---- one ray ---------------------------------------------------------------------------- */

static void trace(const rctx *c, double px, double py, float out[4])
{
    if (px < c->foot[0] || px > c->foot[2] || py < c->foot[1] || py > c->foot[3]) {
        /* outside the box's footprint: what the loop below gives a ray that misses the box */
        const float C = 0, T = 1;
        for (int k = 0; k < 3; ++k) out[k] = C + T * c->bg[k];
        out[3] = (1.0f - T) + T * c->bg[3];
        return;
    }
    ray r;
    r_camera_ray(&c->cam, px, py, r.o, r.d);
    const hv_transform *xf = &c->s->xf;
    double tmin = 0, tmax = HUGE_VAL; /* ortho rays start on the plane through the eye */
    for (int a = 0; a < 3; ++a) {
        r.oi[a] = (r.o[a] - xf->origin[a]) / xf->voxel[a];
        r.di[a] = r.d[a] / xf->voxel[a];
        if (r.di[a] != 0) {
            double t0 = (c->box_lo[a] - r.oi[a]) / r.di[a], t1 = (c->box_hi[a] - r.oi[a]) / r.di[a];
            if (t0 > t1) {
                double tt = t0;
                t0 = t1;
                t1 = tt;
            }
            tmin = HV_MAX(tmin, t0);
            tmax = HV_MIN(tmax, t1);
        } else if (r.oi[a] <= c->box_lo[a] || r.oi[a] >= c->box_hi[a]) {
            tmax = -HUGE_VAL;
        }
    }
    for (int a = 0; a < 3; ++a) {
        r.tdelta8[a] = r.di[a] > 0 ? 8.0 / r.di[a] : r.di[a] < 0 ? -8.0 / r.di[a] : HUGE_VAL;
        r.dp[a] = (float)(c->dt * r.di[a]);
    }
    r.dp[3] = 0;
    r.a.C = (v4f){0, 0, 0, 0};
    r.a.T = 1;
    r.a.done = 0;
    if (tmin < tmax) {
        float V[3] = {(float)-r.d[0], (float)-r.d[1], (float)-r.d[2]}, hl = 0;
        for (int a = 0; a < 3; ++a) {
            r.H[a] = c->L[a] + V[a];
            hl += r.H[a] * r.H[a];
        }
        hl = hl > 0 ? 1.0f / sqrtf(hl) : 0;
        for (int a = 0; a < 3; ++a) r.H[a] *= hl;
        double iv[HV_RENDER_MAX_CLIPS + 1][2];
        int cut[HV_RENDER_MAX_CLIPS + 1];
        int n = kept_intervals(c, &r, tmin, tmax, iv, cut);
        for (int i = 0; i < n && !r.a.done; ++i) {
            r.next_n = (int64_t)floor(iv[i][0] / c->dt) + 1;
            r.prev_cov = 0;
            r.prev_t = iv[i][0];
            if (cut[i] >= 0) {
                const cplane *pl =
                    &c->planes[cut[i] / HV_CLIP_MAX_PLANES][cut[i] % HV_CLIP_MAX_PLANES];
                cut_face(c, &r, iv[i][0], pl->n);
                if (r.a.done) break;
                /* the surface search continues from inside the cut */
                double p[3];
                v4f og;
                ray_point(&r, iv[i][0], p);
                sample_point(c->s, p, &og, NULL);
                r.prev_cov = og[0] * (1.0f / 255.0f);
            }
            march(c, &r, iv[i][0], iv[i][1]);
        }
    }
    for (int k = 0; k < 3; ++k) out[k] = r.a.C[k] + r.a.T * c->bg[k];
    out[3] = (1.0f - r.a.T) + r.a.T * c->bg[3];
}

static hv_status render_tiles(void *vctx, size_t begin, size_t end, int thread)
{
    (void)thread;
    const rctx *c = vctx;
    const int S = c->o->samples;
    const float inv = 1.0f / (float)(S * S);
    for (size_t tile = begin; tile < end; ++tile) {
        int tx = (int)(tile % (size_t)c->tiles_x), ty = (int)(tile / (size_t)c->tiles_x);
        int x0 = tx * c->tile, y0 = ty * c->tile;
        int x1 = HV_MIN(x0 + c->tile, c->img->width), y1 = HV_MIN(y0 + c->tile, c->img->height);
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                float acc[4] = {0, 0, 0, 0}, px[4];
                for (int sy = 0; sy < S; ++sy)
                    for (int sx = 0; sx < S; ++sx) {
                        trace(c, x + (sx + 0.5) / S, y + (sy + 0.5) / S, px);
                        for (int k = 0; k < 4; ++k) acc[k] += px[k];
                    }
                float *dst = c->img->rgba + 4 * ((size_t)y * (size_t)c->img->width + (size_t)x);
                for (int k = 0; k < 4; ++k) dst[k] = S == 1 ? acc[k] : acc[k] * inv;
            }
    }
    return HV_OK;
}

hv_status hv_render_scene_image(const hv_render_scene *s, const hv_render_options *o,
                                const hv_progress *progress, hv_image **out)
{
    *out = NULL;
    hv_status st = hv_render_options_check(o);
    if (st != HV_OK) return st;
    /* the image (float RGBA) and its 8-bit copy for writing, planned before either exists */
    double need = (double)o->width * (double)o->height * 20.0;
    uint64_t budget = hv_memory_budget(o->max_memory);
    if (budget && need > (double)budget) {
        char a[32], b[32];
        return hv_error_option(HV_ERR_LIMIT, "render: an image of %d x %d pixels needs about %s, more than the limit of "
                                             "%s ({max_memory})",
                               o->width, o->height, hv_size_text(a, sizeof a, need), hv_size_text(b, sizeof b, (double)budget));
    }
    rctx *c = hv_calloc(1, sizeof *c);
    if (!c) return HV_ERR_NOMEM;
    c->s = s;
    c->o = o;
    st = r_camera_setup(s, o, &c->cam);
    if (st != HV_OK) goto done;
    st = hv_image_create_unset(o->width, o->height, &c->img); /* every pixel is written below */
    if (st != HV_OK) goto done;

    double vmin = HV_MIN(s->xf.voxel[0], HV_MIN(s->xf.voxel[1], s->xf.voxel[2]));
    double step = o->step > 0 ? o->step : o->mode == HV_RENDER_SURFACE ? 0.5 : 1.0;
    c->dt = step * vmin;
    c->idt = 1.0 / c->dt;
    c->march = march_variant();
    for (int a = 0; a < 3; ++a) c->ivox[a] = (float)(1.0 / s->xf.voxel[a]);
    double lo[3], hi[3], ext = 0;
    r_scene_box(s, lo, hi);
    for (int a = 0; a < 3; ++a) {
        ext = HV_MAX(ext, hi[a] - lo[a]);
        c->box_lo[a] = (double)s->lo[a] - 1.0;
        c->box_hi[a] = (double)s->hi[a] + 1.0;
    }
    c->density = (float)(o->density > 0 ? o->density : (ext > 0 ? 16.0 / ext : 1.0));
    c->tf_lo = (float)o->tf_low;
    c->tf_scale = (float)(1.0 / (o->tf_high - o->tf_low));
    {
        /* full coverage, as the general path computes it, gives ramp exactly 1 (the solid
         * path's assumption) for the default transfer function */
        volatile float full = 255.0f;
        float cov = full * (1.0f / 255.0f), ramp = (cov - c->tf_lo) * c->tf_scale;
        c->solid_cells = cov > c->tf_lo && (ramp > 1 ? 1 : ramp) == 1.0f;
    }
    c->iso = (float)o->iso;
    for (int i = 0; i <= OPACITY_N + 1; ++i)
        c->opacity[i] = (float)(1.0 - exp(-(double)c->density * c->dt *
                                          (double)HV_MIN(i, OPACITY_N) / OPACITY_N));
    for (int i = 0; i < 256; ++i) c->op_byte[i] = opacity_of(c, (float)i * (1.0f / 255.0f));
    c->ka = o->flat ? 1.0f : (float)o->ambient;
    c->kd = o->flat ? 0.0f : (float)o->diffuse;
    c->ks = o->flat ? 0.0f : (float)o->specular;
    c->shin = (float)o->shininess;
    double L[3], ll = 0;
    for (int a = 0; a < 3; ++a) {
        L[a] = o->light[0] * c->cam.right[a] + o->light[1] * c->cam.up[a] -
               o->light[2] * c->cam.fwd[a];
        ll += L[a] * L[a];
    }
    for (int a = 0; a < 3; ++a) c->L[a] = (float)(L[a] / sqrt(ll));
    for (int k = 0; k < 3; ++k) c->bg[k] = o->background[k] * o->background[3];
    c->bg[3] = o->background[3];
    c->nclips = o->clips;
    for (int k = 0; k < o->clips; ++k) {
        c->nplanes[k] = o->clip[k].planes;
        for (int p = 0; p < o->clip[k].planes; ++p) {
            const double *n = o->clip[k].normal[p];
            double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (int a = 0; a < 3; ++a) c->planes[k][p].n[a] = n[a] / nn;
            c->planes[k][p].off = o->clip[k].offset[p] / nn;
        }
    }
    {
        /* the footprint of the box the rays are clipped to (trace) */
        double wlo[3], whi[3];
        for (int a = 0; a < 3; ++a) {
            wlo[a] = s->xf.origin[a] + c->box_lo[a] * s->xf.voxel[a];
            whi[a] = s->xf.origin[a] + c->box_hi[a] * s->xf.voxel[a];
        }
        if (s->empty || !r_camera_footprint(&c->cam, wlo, whi, c->foot)) {
            c->foot[0] = c->foot[1] = -HUGE_VAL;
            c->foot[2] = c->foot[3] = HUGE_VAL;
        }
    }
    c->tile = TILE;
    for (;;) {
        c->tiles_x = (o->width + c->tile - 1) / c->tile;
        c->tiles_y = (o->height + c->tile - 1) / c->tile;
        if (c->tile <= 4 || (int64_t)c->tiles_x * c->tiles_y >= 4 * (int64_t)hv_threads()) break;
        c->tile /= 2;
    }
    if (s->empty) { /* nothing but background */
        for (size_t i = 0; i < (size_t)o->width * (size_t)o->height; ++i)
            memcpy(c->img->rgba + 4 * i, c->bg, sizeof c->bg);
        st = hv_progress_report(progress, "render", 1.0);
    } else {
        st = hv_parallel_for((size_t)c->tiles_x * (size_t)c->tiles_y, 1, render_tiles, c, progress,
                             "render");
    }
done:
    if (st == HV_OK) {
        *out = c->img;
    } else {
        hv_image_destroy(c->img);
    }
    free(c);
    return st;
}

hv_status hv_render(const hv_volume *vol, const hv_render_options *opt, const hv_progress *progress,
                    hv_image **out)
{
    *out = NULL;
    hv_status st = hv_render_options_check(opt);
    if (st != HV_OK) return st;
    hv_render_scene *s;
    st = hv_render_scene_create_lazy(vol, progress, &s);
    if (st != HV_OK) return st;
    st = hv_render_scene_image(s, opt, progress, out);
    hv_render_scene_destroy(s);
    return st;
}
