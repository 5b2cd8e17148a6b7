/* renderer/scene.c - the render-ready form of a graded model (Wu 2.3): each voxel's colour
 * sum p_j * colour_j, occupancy and Sobel-smoothed occupancy gradient, in 9^3 bricks (8^3 block
 * plus apron) reached through a two-level block table (64^3 macro cells, 8^3 blocks) that the
 * ray caster also walks to skip empty space. The table is built at once; a brick is filled from
 * the model when a ray first reaches it (or all of them, in parallel, for a scene that outlives
 * its model). */
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdlib.h>
#include <string.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/internal.h"
#include "hovox/model.h"
#include "render_internal.h"

/* Guards against absurdly spread-out volumes: the dense top level of the block table. */
#define MAX_TOP_CELLS (1u << 26)

void r_scene_box(const hv_render_scene *s, double lo[3], double hi[3])
{
    for (int a = 0; a < 3; ++a) {
        lo[a] = s->xf.origin[a] + ((double)s->lo[a] - 0.5) * s->xf.voxel[a];
        hi[a] = s->xf.origin[a] + ((double)s->hi[a] + 0.5) * s->xf.voxel[a];
    }
}

int hv_render_scene_bounds(const hv_render_scene *s, double lo[3], double hi[3])
{
    if (s->empty) return 0;
    r_scene_box(s, lo, hi);
    return 1;
}

int hv_render_scene_materials(const hv_render_scene *s) { return s->materials; }

void hv_render_scene_destroy(hv_render_scene *s)
{
    if (!s) return;
    free(s->top);
    free(s->pages);
    free(s->bricks);
    free(s->cells);
    free(s->brick_block);
    free(s->brick_kind);
    free(s->brick_alpha);
    free((void *)s->brick_slot);
    free(s->occ);
    free(s);
}

/* Page of block (bx,by,bz), created on demand; NULL on allocation failure. */
static rpage *page_of(hv_render_scene *s, size_t *pcap, const int32_t b[3])
{
    int32_t m[3];
    for (int a = 0; a < 3; ++a) m[a] = r_floor_shift(b[a], 3) - s->mlo[a];
    int64_t cell = ((int64_t)m[0] * s->mdims[1] + m[1]) * s->mdims[2] + m[2];
    if (s->top[cell] < 0) {
        if (hv_grow((void **)&s->pages, pcap, s->npages + 1, sizeof(rpage)) != HV_OK) return NULL;
        rpage *p = &s->pages[s->npages];
        for (int i = 0; i < 512; ++i) p->brick[i] = p->occ[i] = -1;
        s->top[cell] = (int32_t)s->npages++;
    }
    return &s->pages[s->top[cell]];
}

/* Occupied-leaf index of block b, or -1. */
static int32_t occ_at(const hv_render_scene *s, int32_t bx, int32_t by, int32_t bz)
{
    int32_t mx = r_floor_shift(bx, 3) - s->mlo[0], my = r_floor_shift(by, 3) - s->mlo[1],
            mz = r_floor_shift(bz, 3) - s->mlo[2];
    if (mx < 0 || my < 0 || mz < 0 || mx >= s->mdims[0] || my >= s->mdims[1] || mz >= s->mdims[2])
        return -1;
    int32_t p = s->top[((int64_t)mx * s->mdims[1] + my) * s->mdims[2] + mz];
    return p < 0 ? -1 : s->pages[p].occ[RP_INDEX(bx, by, bz)];
}

static uint8_t to_u8(float v)
{
    v = v * 255.0f + 0.5f;
    return (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v);
}

/* Gradient filter: central differences of the occupancy smoothed by the binomial kernel
 * [1 6 15 20 15 6 1] / 64 along each axis (a discrete Gaussian, sigma 1.22 voxels). Binary
 * occupancy has only a few gradient directions; the smoothing turns the staircase of a
 * voxelized sphere into smooth normals. A flat face gives |g| = (42 - 7) * 64 * 64 = 143360,
 * stored divided by GRAD_SCALE (as 128). */
#define GRAD_SCALE 1120
#define KR 3 /* kernel radius */

/* smoothed value of a 7-bit window of a row of occupancy bits */
static int32_t g_window[128];
static pthread_once_t g_window_once = PTHREAD_ONCE_INIT;

static void init_window(void)
{
    static const int W7[7] = {1, 6, 15, 20, 15, 6, 1};
    for (int m = 0; m < 128; ++m) {
        int v = 0;
        for (int k = 0; k < 7; ++k) v += ((m >> k) & 1) * W7[k];
        g_window[m] = v;
    }
}

static uint8_t grad_u8(int g)
{
    int v = (g >= 0 ? g + GRAD_SCALE / 2 : g - GRAD_SCALE / 2) / GRAD_SCALE;
    return (uint8_t)(128 + (v < -127 ? -127 : v > 127 ? 127 : v));
}

/* Colour of occupied voxel n of a leaf whose material buffers are mat[0..nmat-1]:
 * sum p_j colour_j / sum p_j. */
static void voxel_colour(const hv_render_scene *s, const float *const *mat, unsigned n, rvox *v)
{
    uint8_t o[4];
    float sum = 0, acc[4] = {0, 0, 0, 0};
    for (int j = 0; j < s->materials; ++j) {
        float p = mat[j][n];
        if (!(p > 0)) continue; /* negative or NaN: no contribution */
        if (p > 1) p = 1;
        sum += p;
        for (int k = 0; k < 4; ++k) acc[k] += p * s->colour[j][k];
    }
    if (sum > 1e-6f) {
        float inv = 1.0f / sum;
        for (int k = 0; k < 4; ++k) o[k] = to_u8(acc[k] * inv);
    } else { /* no material: grey */
        o[0] = o[1] = o[2] = to_u8(0.7f);
        o[3] = 255;
    }
    v->r = o[0];
    v->g = o[1];
    v->b = o[2];
    v->a = o[3];
}

/* The colours of voxels n..n+3 of a leaf (occupied or not) as RGBA bytes, r first: what
 * voxel_colour gives each, four at a time (the same float operations lane by lane; a fraction
 * that voxel_colour skips adds 0 here, which changes no sum). */
static void colour4(const hv_render_scene *s, const float *const *mat, unsigned n, uint32_t out[4])
{
#if defined(__SSE2__)
    const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
    __m128 sum = zero, acc[4] = {zero, zero, zero, zero};
    for (int j = 0; j < s->materials; ++j) {
        __m128 p = _mm_loadu_ps(mat[j] + n);
        p = _mm_and_ps(_mm_cmpgt_ps(p, zero), _mm_min_ps(p, one)); /* NaN and p <= 0: 0 */
        sum = _mm_add_ps(sum, p);
        for (int k = 0; k < 4; ++k) acc[k] = _mm_add_ps(acc[k], _mm_mul_ps(p, _mm_set1_ps(s->colour[j][k])));
    }
    __m128 valid = _mm_cmpgt_ps(sum, _mm_set1_ps(1e-6f)), inv = _mm_div_ps(one, sum);
    __m128i ch[4];
    for (int k = 0; k < 4; ++k) { /* to_u8 */
        __m128 v = _mm_add_ps(_mm_mul_ps(_mm_mul_ps(acc[k], inv), _mm_set1_ps(255.0f)), _mm_set1_ps(0.5f));
        v = _mm_min_ps(_mm_max_ps(v, zero), _mm_set1_ps(255.0f));
        __m128i grey = _mm_set1_epi32(k < 3 ? to_u8(0.7f) : 255);
        __m128i m = _mm_castps_si128(valid);
        ch[k] = _mm_or_si128(_mm_and_si128(m, _mm_cvttps_epi32(v)), _mm_andnot_si128(m, grey));
    }
    __m128i x = _mm_packus_epi16(_mm_packs_epi32(ch[0], ch[1]), _mm_packs_epi32(ch[2], ch[3]));
    __m128i rg = _mm_unpacklo_epi8(x, _mm_srli_si128(x, 4)), ba = _mm_unpacklo_epi8(_mm_srli_si128(x, 8), _mm_srli_si128(x, 12));
    _mm_storeu_si128((__m128i *)(void *)out, _mm_unpacklo_epi16(rg, ba));
#else
    for (int i = 0; i < 4; ++i) {
        rvox v;
        voxel_colour(s, mat, n + (unsigned)i, &v);
        memcpy(&out[i], &v, 4);
    }
#endif
}

/* The cell bits of a brick (render_internal.h): per voxel, rows along z of "unoccupied" and of
 * "occupied, zero gradient", and of those the cells whose eight corners all have it; the alpha
 * its occupied voxels share, or -1. */
static void fill_cells(const rvox *out, uint64_t *cells, int16_t *alpha)
{
    uint32_t E[RB_DIM][RB_DIM], S[RB_DIM][RB_DIM];
    int a = -2; /* the occupied voxels' alpha: -2 none yet, -1 not one */
    for (int x = 0; x < RB_DIM; ++x)
        for (int y = 0; y < RB_DIM; ++y) {
            uint32_t e = 0, f = 0;
            for (int z = 0; z < RB_DIM; ++z) {
                const rvox *v = &out[RB_INDEX(x, y, z)];
                e |= (uint32_t)(v->occ == 0) << z;
                f |= (uint32_t)(v->occ == 255 && v->gx == 128 && v->gy == 128 && v->gz == 128) << z;
                if (v->occ && a != v->a) a = a == -2 ? v->a : -1;
            }
            E[x][y] = e;
            S[x][y] = f;
        }
    *alpha = (int16_t)(a < 0 ? -1 : a);
    for (int x = 0; x < 8; ++x) {
        uint64_t we = 0, ws = 0;
        for (int y = 0; y < 8; ++y) {
            uint32_t e = E[x][y] & E[x][y + 1] & E[x + 1][y] & E[x + 1][y + 1];
            uint32_t f = S[x][y] & S[x][y + 1] & S[x + 1][y] & S[x + 1][y + 1];
            we |= (uint64_t)(e & (e >> 1) & 0xFFu) << (8 * y);
            ws |= (uint64_t)(f & (f >> 1) & 0xFFu) << (8 * y);
        }
        cells[x] = we;
        cells[8 + x] = ws;
    }
}

/* A brick's neighbourhood: the occupancy rows cover local -(KR + 1) .. 8 + KR + 1 (FB_N), the
 * smoothed occupancy local -1..9 (FB_M), padded along z to whole vectors (FB_MZ). */
enum { FB_N = 9 + 2 * (KR + 1), FB_M = 9 + 2, FB_MZ = 12 };
#define FB_FULL ((1u << FB_N) - 1)

/* The occupied-leaf indices of the 3^3 blocks around brick bi's first block (nb, -1 where
 * none); whether all 27 are full leaves. */
static int brick_neighbours(const hv_render_scene *s, size_t bi, int32_t nb[3][3][3])
{
    const int32_t *B = s->brick_block + 3 * bi;
    int full = 1;
    for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz) {
                int32_t o = occ_at(s, B[0] + dx, B[1] + dy, B[2] + dz);
                nb[dx + 1][dy + 1][dz + 1] = o;
                full &= o >= 0 && s->occ[o].full;
            }
    return full;
}

/* Occupancy bits of the FB_N^3 neighbourhood as rows along z (bit z: local z - (KR + 1));
 * *any when a bit is set, *all when every bit is. */
static void brick_rows(const hv_render_scene *s, const int32_t nb[3][3][3], uint32_t rows[FB_N][FB_N], int *any,
                       int *all)
{
    const r_occ *occ = s->occ;
    /* row (x, y) of a block along z is byte y of its mask word x */
    for (int x = 0; x < FB_N; ++x) {
        int lx = x - (KR + 1), bx = lx < 0 ? 0 : lx > 7 ? 2 : 1;
        for (int y = 0; y < FB_N; ++y) {
            int ly = y - (KR + 1), by = ly < 0 ? 0 : ly > 7 ? 2 : 1;
            uint32_t row = 0;
            for (int bz = 0; bz < 3; ++bz) {
                int32_t o = nb[bx][by][bz];
                if (o < 0) continue;
                uint32_t byte = (uint32_t)(occ[o].mask[lx & 7] >> (8 * (ly & 7))) & 0xFFu;
                row |= bz == 0 ? byte >> (8 - (KR + 1)) : bz == 1 ? byte << (KR + 1) : byte << (KR + 9);
            }
            row &= FB_FULL;
            rows[x][y] = row;
            *any |= row != 0;
            *all &= row == FB_FULL;
        }
    }
}

/* The occupancy rows smoothed separably by the binomial kernel (GRAD_SCALE's comment): z by
 * the 7-bit window table, then y, then x, into S over local -1..9. */
static void brick_smooth(const uint32_t rows[FB_N][FB_N], int32_t S[FB_M][FB_M][FB_MZ])
{
    int32_t T1[FB_N][FB_N][FB_MZ] __attribute__((aligned(16))), T2[FB_N][FB_M][FB_MZ] __attribute__((aligned(16)));
    for (int x = 0; x < FB_N; ++x)
        for (int y = 0; y < FB_N; ++y) {
            uint32_t row = rows[x][y];
            int32_t *t = T1[x][y];
            if (row == 0 || row == FB_FULL) {
                for (int z = 0; z < FB_MZ; ++z) t[z] = row ? 64 : 0;
            } else {
                for (int z = 0; z < FB_M; ++z) t[z] = g_window[(row >> z) & 127u];
                t[FB_M] = 0;
            }
        }
    for (int x = 0; x < FB_N; ++x)
        for (int y = 0; y < FB_M; ++y) {
            int32_t *t = T2[x][y];
            const int32_t *a0 = T1[x][y], *a1 = T1[x][y + 1], *a2 = T1[x][y + 2], *a3 = T1[x][y + 3],
                          *a4 = T1[x][y + 4], *a5 = T1[x][y + 5], *a6 = T1[x][y + 6];
            for (int z = 0; z < FB_MZ; ++z)
                t[z] = a0[z] + a6[z] + 6 * (a1[z] + a5[z]) + 15 * (a2[z] + a4[z]) + 20 * a3[z];
        }
    for (int x = 0; x < FB_M; ++x)
        for (int y = 0; y < FB_M; ++y) {
            int32_t *t = S[x][y];
            const int32_t *a0 = T2[x][y], *a1 = T2[x + 1][y], *a2 = T2[x + 2][y], *a3 = T2[x + 3][y],
                          *a4 = T2[x + 4][y], *a5 = T2[x + 5][y], *a6 = T2[x + 6][y];
            for (int z = 0; z < FB_MZ; ++z)
                t[z] = a0[z] + a6[z] + 6 * (a1[z] + a5[z]) + 15 * (a2[z] + a4[z]) + 20 * a3[z];
        }
}

/* Per voxel of the 9^3 brick: the composition colour (grey without a table) where occupied, and
 * the central differences of S (128s when flat: then every row is `fill`, all set or none). */
static void brick_voxels(const hv_render_scene *s, const int32_t nb[3][3][3], const uint32_t rows[FB_N][FB_N],
                         int flat, uint32_t fill, const int32_t S[FB_M][FB_M][FB_MZ], rvox *out)
{
    /* material buffers of the (up to) 8 leaves the brick's voxels lie in */
    const float *mat[2][2][2][HV_MAX_MATERIALS];
    for (int d = 0; d < 8; ++d) {
        int32_t o = nb[1 + (d >> 2)][1 + ((d >> 1) & 1)][1 + (d & 1)];
        for (int j = 0; j < s->materials && o >= 0; ++j)
            mat[d >> 2][(d >> 1) & 1][d & 1][j] = hv_volume_leaf_float_c(s->vol, s->grids[j], s->occ[o].leaf);
    }
    for (int x = 0; x < RB_DIM; ++x)
        for (int y = 0; y < RB_DIM; ++y) {
            uint32_t row = flat ? fill : rows[x + KR + 1][y + KR + 1];
            /* the row's colours: z 0-7 from the block's leaf four at a time, z 8 from the next */
            uint32_t col[RB_DIM];
            const int32_t o0 = nb[1 + (x >> 3)][1 + (y >> 3)][1], o8 = nb[1 + (x >> 3)][1 + (y >> 3)][2];
            if (s->materials && o0 >= 0 && ((row >> (KR + 1)) & 0xFFu)) {
                colour4(s, mat[x >> 3][y >> 3][0], HV_LEAF_OFFSET(x, y, 0), col);
                colour4(s, mat[x >> 3][y >> 3][0], HV_LEAF_OFFSET(x, y, 4), col + 4);
            }
            if (s->materials && o8 >= 0 && ((row >> (KR + 9)) & 1u)) {
                rvox c8;
                voxel_colour(s, mat[x >> 3][y >> 3][1], HV_LEAF_OFFSET(x, y, 8), &c8);
                memcpy(&col[8], &c8, 4);
            }
            for (int z = 0; z < RB_DIM; ++z) {
                rvox *v = &out[RB_INDEX(x, y, z)];
                int32_t o = z < 8 ? o0 : o8;
                if (((row >> (z + KR + 1)) & 1u) && o >= 0) {
                    if (s->materials) {
                        memcpy(v, &col[z], 4);
                    } else { /* no table: grey */
                        v->r = v->g = v->b = to_u8(0.7f);
                        v->a = 255;
                    }
                    v->occ = 255;
                } else {
                    v->r = v->g = v->b = v->a = 0;
                    v->occ = 0;
                }
                if (flat) {
                    v->gx = v->gy = v->gz = 128;
                    continue;
                }
                v->gx = grad_u8(S[x + 2][y + 1][z + 1] - S[x][y + 1][z + 1]);
                v->gy = grad_u8(S[x + 1][y + 2][z + 1] - S[x + 1][y][z + 1]);
                v->gz = grad_u8(S[x + 1][y + 1][z + 2] - S[x + 1][y + 1][z]);
            }
        }
}

/* Fill brick bi into out: occupancy bits of the 17^3 neighbourhood (local -4..12) as rows
 * along z, smoothed separably into S over local -1..9, then per voxel of the 9^3 brick the
 * composition colour and the central differences of S. Returns its kind. */
static uint8_t fill_brick(const hv_render_scene *s, size_t bi, rvox *out, uint64_t *cells, int16_t *alpha)
{
    uint32_t rows[FB_N][FB_N];
    int32_t S[FB_M][FB_M][FB_MZ] __attribute__((aligned(16)));
    int32_t nb[3][3][3];
    int full = brick_neighbours(s, bi, nb);
    /* deep inside a solid: all occupied, zero gradient */
    int flat = full, any = 0, all = 1;
    if (!full) {
        brick_rows(s, nb, rows, &any, &all);
        flat = !any || all;
    }
    int solid = flat && (full || all);
    if (!flat) brick_smooth(rows, S);
    brick_voxels(s, nb, rows, flat, (full || all) ? FB_FULL : 0, S, out);
    uint8_t kind = RB_GENERAL;
    if (solid) {
        kind = RB_UNIFORM;
        for (int i = 1; i < RB_VOX && kind == RB_UNIFORM; ++i)
            if (memcmp(&out[i], &out[0], sizeof *out) != 0) kind = RB_SOLID;
    }
    fill_cells(out, cells, alpha);
    return kind;
}

/* A painted model's requested colours (hv_colour_paint's grids colour.r, .g, .b where colour.mask
 * is set) replace the composition's colour of brick bi's occupied voxels: the preview shows the
 * part in the sRGB colours asked for, not in a mixture of the resins' display colours (issue 29);
 * the alpha stays the composition's. A uniform brick that the colours make varied becomes solid. */
static void paint_brick(const hv_render_scene *s, size_t bi, rvox *out, uint8_t *kind)
{
    const int32_t *B = s->brick_block + 3 * bi;
    const float *c[2][2][2][4];
    for (int d = 0; d < 8; ++d) {
        int32_t o = occ_at(s, B[0] + (d >> 2), B[1] + ((d >> 1) & 1), B[2] + (d & 1));
        for (int k = 0; k < 4; ++k)
            c[d >> 2][(d >> 1) & 1][d & 1][k] = o >= 0 ? hv_volume_leaf_float_c(s->vol, s->paint[k], s->occ[o].leaf) : NULL;
    }
    for (int x = 0; x < RB_DIM; ++x)
        for (int y = 0; y < RB_DIM; ++y)
            for (int z = 0; z < RB_DIM; ++z) {
                rvox *v = &out[RB_INDEX(x, y, z)];
                const float *const *g = c[x >> 3][y >> 3][z >> 3];
                unsigned n = HV_LEAF_OFFSET(x & 7, y & 7, z & 7);
                if (!v->occ || !g[3] || !(g[3][n] > 0.5f)) continue;
                v->r = to_u8(g[0][n]);
                v->g = to_u8(g[1][n]);
                v->b = to_u8(g[2][n]);
            }
    if (*kind == RB_UNIFORM)
        for (int i = 1; i < RB_VOX && *kind == RB_UNIFORM; ++i)
            if (memcmp(&out[i], &out[0], sizeof *out) != 0) *kind = RB_SOLID;
}

int32_t r_brick_fill(const hv_render_scene *cs, int32_t b)
{
    /* the lazy part of a scene is shared state under brick_slot: filling is not a change a
     * reader of the const scene can see, only when it happens */
    hv_render_scene *s = (hv_render_scene *)cs;
    int32_t slot = -1;
    if (atomic_compare_exchange_strong_explicit(&s->brick_slot[b], &slot, -2, memory_order_acq_rel,
                                                memory_order_acquire)) {
        size_t at = atomic_fetch_add_explicit(&s->nslots, 1, memory_order_relaxed);
        s->brick_kind[b] = fill_brick(s, (size_t)b, s->bricks + at * RB_VOX, s->cells + at * RC_WORDS, &s->brick_alpha[b]);
        if (s->painted) paint_brick(s, (size_t)b, s->bricks + at * RB_VOX, &s->brick_kind[b]);
        atomic_store_explicit(&s->brick_slot[b], (int32_t)at, memory_order_release);
        return (int32_t)at;
    }
    for (int spins = 0; slot < 0; ++spins) { /* another thread fills it: a few microseconds */
#if defined(__SSE2__)
        if (spins < 256) _mm_pause(); else
#endif
            sched_yield();
        slot = atomic_load_explicit(&s->brick_slot[b], memory_order_acquire);
    }
    return slot;
}

/* Fill bricks [begin, end) into their own slots (a scene built eagerly). */
static hv_status fill_range(void *vctx, size_t begin, size_t end, int thread)
{
    (void)thread;
    hv_render_scene *s = vctx;
    for (size_t b = begin; b < end; ++b) {
        s->brick_kind[b] = fill_brick(s, b, s->bricks + b * RB_VOX, s->cells + b * RC_WORDS, &s->brick_alpha[b]);
        if (s->painted) paint_brick(s, b, s->bricks + b * RB_VOX, &s->brick_kind[b]);
        atomic_store_explicit(&s->brick_slot[b], (int32_t)b, memory_order_relaxed);
    }
    return HV_OK;
}



/* A painted model's colour grids that paint_brick reads (and hv_render_volume_load loads; not
 * colour.depth, which only the stack uses). */
static const char *const k_paint[4] = {"colour.r", "colour.g", "colour.b", "colour.mask"};

static void find_paint(hv_render_scene *s, const hv_volume *vol)
{
    s->painted = s->materials > 0;
    for (int k = 0; k < 4; ++k) {
        s->paint[k] = hv_volume_grid_find(vol, k_paint[k]);
        s->painted &= s->paint[k] >= 0 && hv_volume_grid_type(vol, s->paint[k]) == HV_GRID_FLOAT;
    }
}

/* The material colours and grids of vol's table (s->materials, grids, colour); a model without
 * a table is grey (no materials). */
static hv_status scene_materials(hv_render_scene *s, const hv_volume *vol)
{
    hv_material_table *t = NULL;
    hv_status st = hv_material_table_load(vol, &t);
    if (st == HV_ERR_NOT_FOUND) {
        hv_error_clear();
        return HV_OK;
    }
    if (st != HV_OK) return st;
    s->materials = hv_material_count(t);
    for (int j = 0; j < s->materials; ++j) {
        s->grids[j] = hv_material_grid(vol, t, j);
        hv_material_color(t, j, s->colour[j]);
    }
    hv_material_table_destroy(t);
    return HV_OK;
}

/* Planned before anything is built: bricks and tables of every block that holds or touches
 * occupied voxels (at most 8 per leaf of nl) within the memory budget. */
static hv_status scene_budget(size_t nl)
{
    double need = (double)nl * (8.0 * 5.9e3 + 2.1e3);
    uint64_t budget = hv_memory_budget(0);
    if (budget && need > (double)budget) {
        char a[32], b[32];
        return hv_error_set(HV_ERR_LIMIT, "render: the scene of %zu voxel blocks needs up to %s, more than the budget of %s",
                            nl, hv_size_text(a, sizeof a, need), hv_size_text(b, sizeof b, (double)budget));
    }
    return HV_OK;
}

/* Widen s's tight voxel bounds by the occupied voxels of leaf o at origin org. */
static void leaf_bounds(hv_render_scene *s, const r_occ *o, const int32_t org[3])
{
    if (o->full) {
        for (int a = 0; a < 3; ++a) {
            s->lo[a] = HV_MIN(s->lo[a], org[a]);
            s->hi[a] = HV_MAX(s->hi[a], org[a] + 7);
        }
        return;
    }
    for (unsigned w = 0; w < 8; ++w)
        for (uint64_t bits = o->mask[w]; bits; bits &= bits - 1) {
            unsigned n = 64 * w + (unsigned)__builtin_ctzll(bits);
            int32_t p[3] = {org[0] + (int32_t)(n >> 6), org[1] + (int32_t)((n >> 3) & 7), org[2] + (int32_t)(n & 7)};
            for (int a = 0; a < 3; ++a) {
                s->lo[a] = HV_MIN(s->lo[a], p[a]);
                s->hi[a] = HV_MAX(s->hi[a], p[a]);
            }
        }
}

/* The occupied leaves of vol, in leaf order, into occ (room for every leaf): active voxels where
 * grid g_occ (when >= 0) is true. Returns their count; sets their block range [blo, bhi] and s's
 * occupied voxel count and tight voxel bounds. */
static size_t scene_occupied(hv_render_scene *s, const hv_volume *vol, int g_occ, r_occ *occ, int32_t blo[3],
                             int32_t bhi[3])
{
    const int32_t *org = hv_volume_leaf_origins(vol);
    size_t nl = hv_volume_leaf_count(vol), nocc = 0;
    for (int a = 0; a < 3; ++a) {
        blo[a] = s->lo[a] = INT32_MAX;
        bhi[a] = s->hi[a] = INT32_MIN;
    }
    for (size_t l = 0; l < nl; ++l) {
        const uint64_t *m = hv_volume_leaf_mask(vol, l);
        const uint64_t *b = g_occ >= 0 ? hv_volume_leaf_bool_c(vol, g_occ, l) : NULL;
        r_occ *o = &occ[nocc];
        uint64_t anyw = 0;
        for (int w = 0; w < 8; ++w) {
            o->mask[w] = b ? m[w] & b[w] : m[w];
            anyw |= o->mask[w];
        }
        if (!anyw) continue;
        o->leaf = l;
        o->full = 1;
        for (int w = 0; w < 8; ++w) o->full &= o->mask[w] == ~0ull;
        for (int a = 0; a < 3; ++a) {
            o->blk[a] = r_floor_shift(org[3 * l + a], 3);
            blo[a] = HV_MIN(blo[a], o->blk[a]);
            bhi[a] = HV_MAX(bhi[a], o->blk[a]);
        }
        for (int w = 0; w < 8; ++w) s->occupied += (uint64_t)__builtin_popcountll(o->mask[w]);
        leaf_bounds(s, o, org + 3 * l);
        ++nocc;
    }
    return nocc;
}

/* The block table over blocks blo-1 .. bhi+1: its dense top level of macro cells and a page
 * for each cell that holds an occupied block, where the block's index in occ is entered. */
static hv_status scene_table(hv_render_scene *s, const r_occ *occ, size_t nocc, const int32_t blo[3],
                             const int32_t bhi[3], size_t *pcap)
{
    uint64_t cells = 1;
    for (int a = 0; a < 3; ++a) {
        s->mlo[a] = r_floor_shift(blo[a] - 1, 3);
        s->mdims[a] = r_floor_shift(bhi[a] + 1, 3) - s->mlo[a] + 1;
        cells *= (uint64_t)s->mdims[a];
    }
    if (cells > MAX_TOP_CELLS)
        return hv_error_set(HV_ERR_LIMIT,
                            "render: the model spans %d x %d x %d macro cells of 64^3 voxels "
                            "(more than %u): too spread out to render",
                            s->mdims[0], s->mdims[1], s->mdims[2], MAX_TOP_CELLS);
    s->top = hv_malloc_array((size_t)cells, sizeof(int32_t));
    if (!s->top) return HV_ERR_NOMEM;
    for (uint64_t i = 0; i < cells; ++i) s->top[i] = -1;
    for (size_t i = 0; i < nocc; ++i) {
        rpage *p = page_of(s, pcap, occ[i].blk);
        if (!p) return HV_ERR_NOMEM;
        p->occ[RP_INDEX(occ[i].blk[0], occ[i].blk[1], occ[i].blk[2])] = (int32_t)i;
    }
    return HV_OK;
}

/* The bricks at B - {0,1}^3 of every occupied block B, numbered in leaf order (s->nbricks,
 * brick_block, the pages' brick entries), and their storage, none filled yet. */
static hv_status scene_bricks(hv_render_scene *s, const r_occ *occ, size_t nocc, size_t *pcap)
{
    size_t bcap = 0;
    for (size_t i = 0; i < nocc; ++i)
        for (int d = 0; d < 8; ++d) {
            int32_t b[3] = {occ[i].blk[0] - (d >> 2), occ[i].blk[1] - ((d >> 1) & 1), occ[i].blk[2] - (d & 1)};
            rpage *p = page_of(s, pcap, b);
            if (!p) return HV_ERR_NOMEM;
            int32_t *slot = &p->brick[RP_INDEX(b[0], b[1], b[2])];
            if (*slot >= 0) continue;
            if (s->nbricks >= (size_t)INT32_MAX) return hv_error_set(HV_ERR_LIMIT, "render: more than 2^31 bricks");
            if (hv_grow((void **)&s->brick_block, &bcap, 3 * (s->nbricks + 1), sizeof(int32_t)) != HV_OK)
                return HV_ERR_NOMEM;
            memcpy(s->brick_block + 3 * s->nbricks, b, sizeof b);
            *slot = (int32_t)s->nbricks++;
        }
    /* only the memory of the bricks rays reach is ever touched in a lazy scene */
    s->bricks = hv_malloc_big(s->nbricks, RB_VOX * sizeof(rvox));
    s->cells = hv_malloc_big(s->nbricks, RC_WORDS * sizeof(uint64_t));
    s->brick_kind = hv_malloc(s->nbricks);
    s->brick_alpha = hv_malloc_array(s->nbricks, sizeof *s->brick_alpha);
    s->brick_slot = hv_malloc_array(s->nbricks, sizeof *s->brick_slot);
    char mb[32];
    if (!s->bricks || !s->cells || !s->brick_kind || !s->brick_alpha || !s->brick_slot)
        return hv_error_set(HV_ERR_NOMEM, "render: out of memory for %zu bricks (%s)", s->nbricks,
                            hv_size_text(mb, sizeof mb, (double)s->nbricks * RB_VOX * sizeof(rvox)));
    for (size_t b = 0; b < s->nbricks; ++b) atomic_init(&s->brick_slot[b], -1);
    return HV_OK;
}

/* The block table of vol's occupied voxels; every brick filled (lazy == 0, progress "prepare")
 * or none. */
static hv_status build(const hv_volume *vol, int lazy, const hv_progress *progress, hv_render_scene **out)
{
    *out = NULL;
    hv_render_scene *s = hv_calloc(1, sizeof *s);
    if (!s) return HV_ERR_NOMEM;
    s->xf = hv_volume_get_transform(vol);
    s->vol = vol;
    atomic_init(&s->nslots, 0);
    r_occ *occ = NULL;
    size_t pcap = 0, nl = hv_volume_leaf_count(vol), nocc;
    int32_t blo[3], bhi[3];
    hv_status st = scene_materials(s, vol);
    if (st != HV_OK) goto fail;
    find_paint(s, vol);

    /* occupied leaves: active voxels where "occupancy" (when present) is true */
    int g_occ = hv_volume_grid_find(vol, "occupancy");
    if (g_occ >= 0 && hv_volume_grid_type(vol, g_occ) != HV_GRID_BOOL) g_occ = -1;
    if ((st = scene_budget(nl)) != HV_OK) goto fail;
    occ = hv_malloc_array(nl ? nl : 1, sizeof *occ);
    if (!occ) {
        st = HV_ERR_NOMEM;
        goto fail;
    }
    nocc = scene_occupied(s, vol, g_occ, occ, blo, bhi);
    if (nocc == 0) {
        s->empty = 1;
        for (int a = 0; a < 3; ++a) s->lo[a] = s->hi[a] = 0;
        free(occ);
        *out = s;
        return hv_progress_report(progress, "prepare", 1.0);
    }
    st = scene_table(s, occ, nocc, blo, bhi, &pcap);
    if (st == HV_OK) st = scene_bricks(s, occ, nocc, &pcap);
    if (st != HV_OK) goto fail;
    s->occ = occ;
    s->nocc = nocc;
    occ = NULL;
    pthread_once(&g_window_once, init_window);
    if (lazy) {
        st = hv_progress_report(progress, "prepare", 1.0);
    } else {
        atomic_store(&s->nslots, s->nbricks);
        st = hv_parallel_for(s->nbricks, 16, fill_range, s, progress, "prepare");
        /* complete: the model is not needed any more */
        s->vol = NULL;
        free(s->occ);
        s->occ = NULL;
    }
    if (st != HV_OK) goto fail;
    *out = s;
    return HV_OK;

fail:
    free(occ);
    hv_render_scene_destroy(s);
    return st;
}

hv_status hv_render_scene_create(const hv_volume *vol, const hv_progress *progress, hv_render_scene **out)
{
    return build(vol, 0, progress, out);
}

hv_status hv_render_scene_create_lazy(const hv_volume *vol, const hv_progress *progress, hv_render_scene **out)
{
    return build(vol, 1, progress, out);
}

hv_status hv_render_volume_load(const char *path, hv_volume **out)
{
    /* what build() reads: the occupancy, the material table's grids (hv_material_grid), a painted
     * model's colours (k_paint) */
    const char *const k_grids[] = {"occupancy", "material.*", k_paint[0], k_paint[1], k_paint[2], k_paint[3]};
    hv_status st = hv_model_load_grids(path, k_grids, (int)(sizeof k_grids / sizeof *k_grids), out);
    int g = st == HV_OK ? hv_volume_grid_find(*out, "occupancy") : 0;
    if (g < 0 || (st == HV_OK && hv_volume_grid_type(*out, g) != HV_GRID_BOOL)) {
        hv_volume_destroy(*out);
        st = hv_model_load(path, out);
    }
    return st;
}
