/* slicing/halftone.c - one material per printer voxel: a 3D blue-noise threshold mask made by
 * void-and-cluster (Ulichney 1993, "The void-and-cluster method for dither array generation"),
 * cached on disk, and vector error diffusion (Floyd-Steinberg weights, serpentine, with a share
 * of the error carried to the next layer). */
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "core/internal.h"
#include "hovox/material.h"
#include "layers_internal.h"

uint64_t hv_hash64(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/* ==== void-and-cluster ======================================================================= */

/* A tournament tree over the cells: each node keeps the tightest cluster (largest energy among
 * ones) and the largest void (smallest energy among zeros) below it, ties to the lower index,
 * so every choice is deterministic. */
typedef struct vac {
    int nx, ny, nz;
    size_t n, p;        /* cells, leaves (power of two) */
    double *e;          /* energy per cell */
    uint8_t *bit;
    double *kw;         /* kernel weights */
    int (*ko)[3];       /* kernel offsets */
    int nk;
    double *hi_v, *lo_v; /* per node */
    int32_t *hi_i, *lo_i;
    uint32_t *stamp, now;
    size_t *list, *list2;
} vac;

static void node_leaf(vac *v, size_t c)
{
    size_t k = v->p + c;
    if (c < v->n && v->bit[c]) {
        v->hi_v[k] = v->e[c];
        v->hi_i[k] = (int32_t)c;
        v->lo_v[k] = INFINITY;
        v->lo_i[k] = -1;
    } else if (c < v->n) {
        v->hi_v[k] = -INFINITY;
        v->hi_i[k] = -1;
        v->lo_v[k] = v->e[c];
        v->lo_i[k] = (int32_t)c;
    } else {
        v->hi_v[k] = -INFINITY;
        v->hi_i[k] = -1;
        v->lo_v[k] = INFINITY;
        v->lo_i[k] = -1;
    }
}

static void node_pull(vac *v, size_t k)
{
    size_t a = 2 * k, b = 2 * k + 1;
    /* the left child holds the lower indices, so it wins ties */
    if (v->hi_v[b] > v->hi_v[a]) {
        v->hi_v[k] = v->hi_v[b];
        v->hi_i[k] = v->hi_i[b];
    } else {
        v->hi_v[k] = v->hi_v[a];
        v->hi_i[k] = v->hi_i[a];
    }
    if (v->lo_v[b] < v->lo_v[a]) {
        v->lo_v[k] = v->lo_v[b];
        v->lo_i[k] = v->lo_i[b];
    } else {
        v->lo_v[k] = v->lo_v[a];
        v->lo_i[k] = v->lo_i[a];
    }
}

static void tree_build(vac *v)
{
    for (size_t c = 0; c < v->p; ++c) node_leaf(v, c);
    for (size_t k = v->p - 1; k >= 1; --k) node_pull(v, k);
}

/* Flip cell c (add a one when `add`, else remove it), update the energies around it and the
 * tree above every touched leaf, level by level without repeats. */
static void vac_flip(vac *v, size_t c, int add)
{
    v->bit[c] = (uint8_t)add;
    int x = (int)(c % (size_t)v->nx), y = (int)(c / (size_t)v->nx % (size_t)v->ny),
        z = (int)(c / ((size_t)v->nx * (size_t)v->ny));
    double sgn = add ? 1.0 : -1.0;
    size_t nl = 0;
    ++v->now;
    /* the kernel holds offset (0, 0, 0), so c's own leaf is refreshed with its new bit */
    for (int k = 0; k < v->nk; ++k) {
        int xx = x + v->ko[k][0], yy = y + v->ko[k][1], zz = z + v->ko[k][2];
        xx = (xx % v->nx + v->nx) % v->nx;
        yy = (yy % v->ny + v->ny) % v->ny;
        zz = (zz % v->nz + v->nz) % v->nz;
        size_t q = ((size_t)zz * (size_t)v->ny + (size_t)yy) * (size_t)v->nx + (size_t)xx;
        v->e[q] += sgn * v->kw[k];
        node_leaf(v, q);
        size_t parent = (v->p + q) >> 1;
        if (v->stamp[parent] != v->now) {
            v->stamp[parent] = v->now;
            v->list[nl++] = parent;
        }
    }
    while (nl) {
        size_t n2 = 0;
        ++v->now;
        for (size_t i = 0; i < nl; ++i) {
            size_t k = v->list[i];
            node_pull(v, k);
            if (k > 1 && v->stamp[k >> 1] != v->now) {
                v->stamp[k >> 1] = v->now;
                v->list2[n2++] = k >> 1;
            }
        }
        size_t *t = v->list;
        v->list = v->list2;
        v->list2 = t;
        nl = n2;
    }
}

static void vac_free(vac *v)
{
    free(v->e);
    free(v->bit);
    free(v->kw);
    free(v->ko);
    free(v->hi_v);
    free(v->lo_v);
    free(v->hi_i);
    free(v->lo_i);
    free(v->stamp);
    free(v->list);
    free(v->list2);
}

hv_status hv_bluenoise_generate(int nx, int ny, int nz, double sigma, uint64_t seed,
                                uint32_t *ranks, const hv_progress *progress)
{
    if (!ranks) return hv_error_set(HV_ERR_INVALID, "blue noise: ranks is NULL");
    if (nx < 2 || ny < 2 || nz < 1 || (double)nx * ny * nz > (double)(1 << 24))
        return hv_error_set(HV_ERR_INVALID, "blue noise: tile %d x %d x %d (each >= 2, nz >= 1, at most 2^24 cells)",
                            nx, ny, nz);
    if (!(sigma >= 0.5 && sigma <= 8))
        return hv_error_set(HV_ERR_INVALID, "blue noise: sigma %g outside [0.5, 8]", sigma);
    vac v;
    memset(&v, 0, sizeof v);
    v.nx = nx;
    v.ny = ny;
    v.nz = nz;
    v.n = (size_t)nx * (size_t)ny * (size_t)nz;
    v.p = 1;
    while (v.p < v.n) v.p <<= 1;
    if (v.p < 2) v.p = 2;
    /* kernel: a ball of radius 3 sigma, cut to half the tile per axis so that no cell is
     * reached twice around the torus */
    int R = (int)ceil(3 * sigma);
    int rx = HV_MIN(R, (nx - 1) / 2), ry = HV_MIN(R, (ny - 1) / 2), rz = HV_MIN(R, (nz - 1) / 2);
    size_t kcap = (size_t)(2 * rx + 1) * (size_t)(2 * ry + 1) * (size_t)(2 * rz + 1);
    v.kw = hv_malloc_array(kcap, sizeof *v.kw);
    v.ko = hv_malloc_array(kcap, sizeof *v.ko);
    v.e = hv_calloc(v.n, sizeof *v.e);
    v.bit = hv_calloc(v.n, 1);
    v.hi_v = hv_malloc_array(2 * v.p, sizeof *v.hi_v);
    v.lo_v = hv_malloc_array(2 * v.p, sizeof *v.lo_v);
    v.hi_i = hv_malloc_array(2 * v.p, sizeof *v.hi_i);
    v.lo_i = hv_malloc_array(2 * v.p, sizeof *v.lo_i);
    v.stamp = hv_calloc(2 * v.p, sizeof *v.stamp);
    v.list = hv_malloc_array(kcap + 2, sizeof *v.list);
    v.list2 = hv_malloc_array(kcap + 2, sizeof *v.list2);
    double *e0 = hv_malloc_array(v.n, sizeof *e0);
    uint8_t *bit0 = hv_malloc(v.n);
    if (!v.kw || !v.ko || !v.e || !v.bit || !v.hi_v || !v.lo_v || !v.hi_i || !v.lo_i || !v.stamp ||
        !v.list || !v.list2 || !e0 || !bit0) {
        vac_free(&v);
        free(e0);
        free(bit0);
        return HV_ERR_NOMEM;
    }
    double r2max = 9 * sigma * sigma;
    for (int dz = -rz; dz <= rz; ++dz)
        for (int dy = -ry; dy <= ry; ++dy)
            for (int dx = -rx; dx <= rx; ++dx) {
                double d2 = (double)(dx * dx + dy * dy + dz * dz);
                if (d2 > r2max) continue;
                v.ko[v.nk][0] = dx;
                v.ko[v.nk][1] = dy;
                v.ko[v.nk][2] = dz;
                v.kw[v.nk] = exp(-d2 / (2 * sigma * sigma));
                ++v.nk;
            }
    hv_status st = HV_OK;
    /* initial binary pattern: 10% ones at random cells */
    size_t ones = HV_MAX(v.n / 10, (size_t)1);
    uint64_t rng = hv_hash64(seed ^ 0x5eedb10eull);
    tree_build(&v);
    for (size_t placed = 0; placed < ones;) {
        rng = hv_hash64(rng);
        size_t c = (size_t)(rng % v.n);
        if (v.bit[c]) continue;
        vac_flip(&v, c, 1);
        ++placed;
    }
    /* relax: move the tightest cluster into the largest void until they coincide */
    for (size_t it = 0; it < v.n; ++it) {
        size_t c = (size_t)v.hi_i[1];
        vac_flip(&v, c, 0);
        size_t g = (size_t)v.lo_i[1];
        vac_flip(&v, g, 1);
        if (g == c) break;
    }
    memcpy(e0, v.e, v.n * sizeof *e0);
    memcpy(bit0, v.bit, v.n);
    size_t total = v.n, done = 0, report = HV_MAX(v.n / 64, (size_t)1);
    /* phase 1: ranks ones-1 .. 0 by removing the tightest cluster */
    for (size_t r = ones; r-- > 0 && st == HV_OK;) {
        size_t c = (size_t)v.hi_i[1];
        ranks[c] = (uint32_t)r;
        vac_flip(&v, c, 0);
        if (++done % report == 0) st = hv_progress_report(progress, "bluenoise", (double)done / (double)total);
    }
    /* phases 2 and 3: ranks ones .. n-1 by filling the largest void (for the second half the
     * tightest cluster of zeros is the largest void of ones: E0 = sum K - E1) */
    memcpy(v.e, e0, v.n * sizeof *e0);
    memcpy(v.bit, bit0, v.n);
    tree_build(&v);
    for (size_t r = ones; r < v.n && st == HV_OK; ++r) {
        size_t g = (size_t)v.lo_i[1];
        ranks[g] = (uint32_t)r;
        vac_flip(&v, g, 1);
        if (++done % report == 0) st = hv_progress_report(progress, "bluenoise", (double)done / (double)total);
    }
    vac_free(&v);
    free(e0);
    free(bit0);
    if (st == HV_OK) st = hv_progress_report(progress, "bluenoise", 1.0);
    return st;
}

/* ==== the cached tile ======================================================================= */

#define TILE_SIGMA 1.5
#define TILE_SEED 20240607u
#define TILE_MAGIC "HVBNTIL1"
#define TILE_NAME "bluenoise-64x64x32-s1.5-v1.bin"

static pthread_mutex_t g_tile_lock = PTHREAD_MUTEX_INITIALIZER;
static uint32_t *g_tile;
static int g_tile_cached;

static void put32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; ++i) p[i] = (uint8_t)(v >> (8 * i));
}
static uint32_t get32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static size_t tile_cells(void) { return (size_t)HV_BLUENOISE_NX * HV_BLUENOISE_NY * HV_BLUENOISE_NZ; }

/* header: magic[8], nx, ny, nz, sigma*1000, seed, crc32 of the rank bytes; then ranks (LE) */
#define TILE_HEADER 32

static int tile_load(const char *path, uint32_t *ranks)
{
    size_t n = tile_cells(), want = TILE_HEADER + 4 * n;
    char *data = NULL;
    size_t size = 0;
    if (hv_read_file(path, want + 1, &data, &size) != HV_OK) {
        hv_error_clear();
        return 0;
    }
    int ok = size == want && memcmp(data, TILE_MAGIC, 8) == 0;
    const uint8_t *h = (const uint8_t *)data;
    if (ok)
        ok = get32(h + 8) == HV_BLUENOISE_NX && get32(h + 12) == HV_BLUENOISE_NY &&
             get32(h + 16) == HV_BLUENOISE_NZ && get32(h + 20) == (uint32_t)(TILE_SIGMA * 1000) &&
             get32(h + 24) == TILE_SEED &&
             get32(h + 28) == (uint32_t)crc32(0L, h + TILE_HEADER, (uInt)(4 * n));
    uint8_t *seen = ok ? calloc(n, 1) : NULL;
    if (ok && !seen) ok = 0;
    for (size_t i = 0; ok && i < n; ++i) {
        uint32_t r = get32(h + TILE_HEADER + 4 * i);
        if (r >= n || seen[r]) ok = 0;
        else {
            seen[r] = 1;
            ranks[i] = r;
        }
    }
    free(seen);
    free(data);
    return ok;
}

static int mkdirs(const char *dir)
{
    char buf[4096];
    size_t n = strlen(dir);
    if (n == 0 || n >= sizeof buf) return -1;
    memcpy(buf, dir, n + 1);
    for (size_t i = 1; i <= n; ++i) {
        if (buf[i] == '/' || buf[i] == '\0') {
            char ch = buf[i];
            buf[i] = '\0';
            if (mkdir(buf, 0777) != 0 && errno != EEXIST) return -1;
            buf[i] = ch;
        }
    }
    struct stat sb;
    return stat(dir, &sb) == 0 && S_ISDIR(sb.st_mode) ? 0 : -1;
}

static void tile_save(const char *dir, const uint32_t *ranks)
{
    if (mkdirs(dir) != 0) return;
    size_t n = tile_cells();
    uint8_t *buf = malloc(TILE_HEADER + 4 * n);
    if (!buf) return;
    memcpy(buf, TILE_MAGIC, 8);
    put32(buf + 8, HV_BLUENOISE_NX);
    put32(buf + 12, HV_BLUENOISE_NY);
    put32(buf + 16, HV_BLUENOISE_NZ);
    put32(buf + 20, (uint32_t)(TILE_SIGMA * 1000));
    put32(buf + 24, TILE_SEED);
    for (size_t i = 0; i < n; ++i) put32(buf + TILE_HEADER + 4 * i, ranks[i]);
    put32(buf + 28, (uint32_t)crc32(0L, buf + TILE_HEADER, (uInt)(4 * n)));
    char path[4200];
    snprintf(path, sizeof path, "%s/%s", dir, TILE_NAME);
    hv_atomic_file af;
    if (hv_atomic_open(&af, path, "wb") == HV_OK) {
        if (fwrite(buf, 1, TILE_HEADER + 4 * n, af.fp) == TILE_HEADER + 4 * n) {
            if (hv_atomic_commit(&af) != HV_OK) hv_error_clear();
        } else {
            hv_atomic_abort(&af);
        }
    }
    hv_error_clear(); /* an unwritable cache is not an error */
    free(buf);
}

static char g_cache_dir[4096];
static int g_cache_set;

void hv_set_cache_dir(const char *dir)
{
    g_cache_set = dir != NULL;
    snprintf(g_cache_dir, sizeof g_cache_dir, "%s", dir ? dir : "");
}

static void default_cache_dir(char *out, size_t size)
{
    if (g_cache_set) {
        snprintf(out, size, "%s", g_cache_dir);
        return;
    }
    const char *x = getenv("XDG_CACHE_HOME");
    if (x && *x == '/') {
        snprintf(out, size, "%s/hovox", x);
        return;
    }
    const char *home = getenv("HOME");
    if (home && *home) snprintf(out, size, "%s/.cache/hovox", home);
    else out[0] = '\0';
}

hv_status hv_bluenoise_tile(const char *cache_dir, const hv_progress *progress,
                            const uint32_t **ranks, int *cached)
{
    if (!ranks) return hv_error_set(HV_ERR_INVALID, "blue noise: ranks is NULL");
    pthread_mutex_lock(&g_tile_lock);
    hv_status st = HV_OK;
    if (!g_tile) {
        char dir[4096];
        if (cache_dir) snprintf(dir, sizeof dir, "%s", cache_dir);
        else default_cache_dir(dir, sizeof dir);
        uint32_t *t = hv_malloc_array(tile_cells(), sizeof *t);
        if (!t) st = HV_ERR_NOMEM;
        char path[4200];
        snprintf(path, sizeof path, "%s/%s", dir, TILE_NAME);
        if (st == HV_OK && dir[0] && tile_load(path, t)) {
            g_tile_cached = 1;
        } else if (st == HV_OK) {
            st = hv_bluenoise_generate(HV_BLUENOISE_NX, HV_BLUENOISE_NY, HV_BLUENOISE_NZ, TILE_SIGMA,
                                       TILE_SEED, t, progress);
            if (st == HV_OK && dir[0]) tile_save(dir, t);
            g_tile_cached = 0;
        }
        if (st == HV_OK) g_tile = t;
        else free(t);
    } else {
        g_tile_cached = 1;
    }
    *ranks = g_tile;
    if (cached) *cached = g_tile_cached;
    pthread_mutex_unlock(&g_tile_lock);
    return st;
}

void hv_bluenoise_offsets(uint64_t seed, int off[3])
{
    uint64_t h = hv_hash64(seed * 0x632be59bd9b4e019ull + 0x1234567ull);
    /* seed 0 keeps the tile where it is, so the default output is easy to reason about */
    if (seed == 0) h = 0;
    off[0] = (int)(h % HV_BLUENOISE_NX);
    off[1] = (int)((h >> 16) % HV_BLUENOISE_NY);
    off[2] = (int)((h >> 32) % HV_BLUENOISE_NZ);
}

/* ==== halftoning kernels ==================================================================== */

/* The material picks of n pixels of one row, in one pass: material j where
 * p_0 + .. + p_{j-1} <= t < p_0 + .. + p_j (the cumulative fractions summed in material order,
 * so every vector width gives the same pick). A zero last fraction is skipped where rounding left
 * the sum of the fractions below t: the last material present takes the pixel. out = 0 outside
 * the mask, else 1 + material; n_j += pixels given material j. M is the material count, a
 * constant where the function is inlined. */
static inline __attribute__((always_inline)) void pick_row(int M, const float *const *f, const float *restrict t,
                                                           const uint8_t *restrict mrow,
                                                           uint8_t *restrict orow, int n, uint32_t *cnt)
{
    /* the planes in restrict locals, so the stores to orow cannot be taken to change them; one
     * step per material written out (no array, no inner loop: both kept gcc from vectorising past
     * four materials), the steps past M dropped as M is a constant */
    const float *restrict f0 = f[0], *restrict f1 = f[M > 1 ? 1 : 0], *restrict f2 = f[M > 2 ? 2 : 0],
                          *restrict f3 = f[M > 3 ? 3 : 0], *restrict f4 = f[M > 4 ? 4 : 0],
                          *restrict f5 = f[M > 5 ? 5 : 0], *restrict f6 = f[M > 6 ? 6 : 0],
                          *restrict f7 = f[M > 7 ? 7 : 0];
#define PICK_STEP(j, fj)                                                                                           \
    if ((j) < M - 1) {                                                                                             \
        float vj = fj[c];                                                                                          \
        cu += vj;                                                                                                  \
        k += tc >= cu;                                                                                             \
        last = vj > 0 ? (j) : last;                                                                                \
    }
#pragma omp simd
    for (int c = 0; c < n; ++c) {
        float cu = 0, tc = t[c];
        int k = 0, last = -1;
        PICK_STEP(0, f0) PICK_STEP(1, f1) PICK_STEP(2, f2) PICK_STEP(3, f3)
        PICK_STEP(4, f4) PICK_STEP(5, f5) PICK_STEP(6, f6)
        float fl = M == 1 ? f0[c] : M == 2 ? f1[c] : M == 3 ? f2[c] : M == 4 ? f3[c] : M == 5 ? f4[c]
                 : M == 6 ? f5[c] : M == 7 ? f6[c] : f7[c];
        last = fl > 0 ? M - 1 : last;
        k = (k == M - 1 && fl <= 0 && last >= 0) ? last : k;
        orow[c] = (uint8_t)(mrow[c] * (k + 1));
    }
#undef PICK_STEP
    for (int j = 0; j < M; ++j) {
        uint32_t v = (uint32_t)j + 1, s = 0;
#pragma omp simd reduction(+ : s)
        for (int c = 0; c < n; ++c) s += orow[c] == v;
        cnt[j] += s;
    }
}

/* Any material count: the same picks, pixel by pixel. */
static void pick_row_m(int m, const float *const *f, const float *t, const uint8_t *mrow, uint8_t *orow, int n,
                       uint32_t *cnt)
{
    for (int c = 0; c < n; ++c) {
        float cu = 0;
        int k = 0, last = -1;
        for (int j = 0; j < m - 1; ++j) {
            cu += f[j][c];
            k += t[c] >= cu;
            last = f[j][c] > 0 ? j : last;
        }
        float fl = f[m - 1][c];
        last = fl > 0 ? m - 1 : last;
        k = (k == m - 1 && fl <= 0 && last >= 0) ? last : k;
        orow[c] = (uint8_t)(mrow[c] * (k + 1));
        cnt[k] += mrow[c];
    }
}

/* The material picks of n pixels of one row (see pick_row); material counts up to 8 (three graded,
 * the six colour resins) are made constant, so their loops unroll and vectorise. */
HV_HOT_CLONES static void pick_row_any(int m, const float *const *f, const float *t, const uint8_t *mrow,
                                          uint8_t *orow, int n, uint32_t *cnt)
{
    switch (m) {
    case 1: pick_row(1, f, t, mrow, orow, n, cnt); break;
    case 2: pick_row(2, f, t, mrow, orow, n, cnt); break;
    case 3: pick_row(3, f, t, mrow, orow, n, cnt); break;
    case 4: pick_row(4, f, t, mrow, orow, n, cnt); break;
    case 5: pick_row(5, f, t, mrow, orow, n, cnt); break;
    case 6: pick_row(6, f, t, mrow, orow, n, cnt); break; /* the six colour resins (issue 29) */
    case 7: pick_row(7, f, t, mrow, orow, n, cnt); break;
    case 8: pick_row(8, f, t, mrow, orow, n, cnt); break;
    default: pick_row_m(m, f, t, mrow, orow, n, cnt); break;
    }
}

/* The target of one row: each material's fractions summed over the object pixels, in float, pixel
 * after pixel (the sums the manifest has always printed), then added to tsum. Only the object
 * pixels are read: a source that writes fractions only at its object pixels (a scan,
 * slicing/scan_source.c) leaves stale floats between them (a stale NaN once made the manifest's
 * targets null). One pass over the pixels carries the M sums side by side: each is still a chain
 * of dependent adds in pixel order (the same bits), but the M chains overlap, where one material
 * after the other waited on every add (the sums were a third of a graded part's halftoning, and
 * twice that with the six colour resins). */
static inline __attribute__((always_inline)) void target_sums(int M, const float *const *f, const uint8_t *mrow,
                                                              int c0, int c1, double *tsum)
{
    /* the sums in named locals, not an array, so they stay in registers */
    const float *f0 = f[0], *f1 = f[M > 1 ? 1 : 0], *f2 = f[M > 2 ? 2 : 0], *f3 = f[M > 3 ? 3 : 0],
                *f4 = f[M > 4 ? 4 : 0], *f5 = f[M > 5 ? 5 : 0], *f6 = f[M > 6 ? 6 : 0], *f7 = f[M > 7 ? 7 : 0];
    float s0 = 0, s1 = 0, s2 = 0, s3 = 0, s4 = 0, s5 = 0, s6 = 0, s7 = 0;
    for (int c = c0; c <= c1; ++c) {
        if (!mrow[c]) continue;
        s0 += f0[c];
        if (M > 1) s1 += f1[c];
        if (M > 2) s2 += f2[c];
        if (M > 3) s3 += f3[c];
        if (M > 4) s4 += f4[c];
        if (M > 5) s5 += f5[c];
        if (M > 6) s6 += f6[c];
        if (M > 7) s7 += f7[c];
    }
    const float s[8] = {s0, s1, s2, s3, s4, s5, s6, s7};
    for (int j = 0; j < M; ++j) tsum[j] += s[j];
}

static void target_row(int m, const float *const *f, const uint8_t *mrow, int c0, int c1, double *tsum)
{
    switch (m) {
    case 1: target_sums(1, f, mrow, c0, c1, tsum); return;
    case 2: target_sums(2, f, mrow, c0, c1, tsum); return;
    case 3: target_sums(3, f, mrow, c0, c1, tsum); return;
    case 4: target_sums(4, f, mrow, c0, c1, tsum); return;
    case 5: target_sums(5, f, mrow, c0, c1, tsum); return;
    case 6: target_sums(6, f, mrow, c0, c1, tsum); return;
    case 7: target_sums(7, f, mrow, c0, c1, tsum); return;
    case 8: target_sums(8, f, mrow, c0, c1, tsum); return;
    default: break;
    }
    for (int j = 0; j < m; j += 8) { /* eight sums at a time */
        int n = HV_MIN(8, m - j);
        float s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
        for (int c = c0; c <= c1; ++c) {
            if (!mrow[c]) continue;
            for (int k = 0; k < n; ++k) s[k] += f[j + k][c];
        }
        for (int k = 0; k < n; ++k) tsum[j + k] += s[k];
    }
}

void hv_halftone_bluenoise(const float *frac, int m, int w, int h, const uint8_t *mask,
                           const uint32_t *ranks, const int off[3], size_t layer, uint8_t *out,
                           uint64_t *counts, double *tsum)
{
    size_t plane = (size_t)w * (size_t)h;
    const float inv = 1.0f / (float)tile_cells();
    int z = (int)((layer + (size_t)off[2]) % HV_BLUENOISE_NZ);
    /* the row's thresholds, rotated by the seed's offset and repeated, so a run of up to RUN
     * pixels from any phase in the tile is contiguous */
    enum { RUN = 1024 };
    float rot[RUN + HV_BLUENOISE_NX];
    const float *f[HV_MAX_MATERIALS];
    uint32_t cnt[HV_MAX_MATERIALS];
    for (int r = 0; r < h; ++r) {
        size_t base = (size_t)r * (size_t)w;
        const uint8_t *mrow = mask + base;
        uint8_t *orow = out + base;
        const uint8_t *hit = memchr(mrow, 1, (size_t)w);
        if (!hit) {
            memset(orow, 0, (size_t)w);
            continue;
        }
        int c0 = (int)(hit - mrow), c1 = (int)((const uint8_t *)memrchr(mrow, 1, (size_t)w) - mrow);
        memset(orow, 0, (size_t)c0);
        memset(orow + c1 + 1, 0, (size_t)(w - 1 - c1));
        int ty = (r + off[1]) % HV_BLUENOISE_NY;
        const uint32_t *trow = ranks + ((size_t)z * HV_BLUENOISE_NY + (size_t)ty) * HV_BLUENOISE_NX;
        for (int i = 0; i < HV_BLUENOISE_NX; ++i)
            rot[i] = ((float)trow[(i + off[0]) & (HV_BLUENOISE_NX - 1)] + 0.5f) * inv;
        for (int i = HV_BLUENOISE_NX; i < (int)HV_COUNT(rot); ++i) rot[i] = rot[i - HV_BLUENOISE_NX];
        for (int j = 0; j < m; ++j) {
            f[j] = frac + (size_t)j * plane + base;
            cnt[j] = 0;
        }
        /* in runs of up to RUN pixels, each starting at its phase in rot */
        for (int c = c0; c <= c1;) {
            int i = c & (HV_BLUENOISE_NX - 1), n = HV_MIN(RUN, c1 - c + 1);
            const float *fc[HV_MAX_MATERIALS];
            for (int j = 0; j < m; ++j) fc[j] = f[j] + c;
            pick_row_any(m, fc, rot + i, mrow + c, orow + c, n, cnt);
            c += n;
        }
        for (int j = 0; j < m; ++j) counts[j] += cnt[j];
        if (tsum) target_row(m, f, mrow, c0, c1, tsum);
    }
}

#define CARRY_Z 0.25f
#define ERR_CLAMP 2.0f

void hv_halftone_diffuse(const float *frac, int m, int w, int h, const uint8_t *mask,
                         float *err, float *next, int serp, uint8_t *out, uint64_t *counts,
                         double *tsum)
{
    size_t plane = (size_t)w * (size_t)h;
    static const float fs[4] = {7.0f / 16, 3.0f / 16, 5.0f / 16, 1.0f / 16};
    float v[HV_MAX_MATERIALS], e[HV_MAX_MATERIALS];
    for (int r = 0; r < h; ++r) {
        int ltr = ((r + serp) & 1) == 0, dx = ltr ? 1 : -1;
        for (int i = 0; i < w; ++i) {
            int c = ltr ? i : w - 1 - i;
            size_t p = (size_t)r * (size_t)w + (size_t)c;
            if (!mask[p]) {
                out[p] = 0;
                continue;
            }
            int best = 0;
            for (int j = 0; j < m; ++j) {
                float tg = frac[(size_t)j * plane + p];
                if (tsum) tsum[j] += tg;
                float a = tg + err[(size_t)j * plane + p];
                v[j] = HV_CLAMP(a, -ERR_CLAMP, 1 + ERR_CLAMP);
                if (v[j] > v[best]) best = j;
            }
            out[p] = (uint8_t)(best + 1);
            counts[best]++;
            for (int j = 0; j < m; ++j) e[j] = v[j] - (j == best ? 1.0f : 0.0f);
            /* neighbours: ahead in the row, then behind / below / ahead in the next row */
            int nc[4] = {c + dx, c - dx, c, c + dx}, nr[4] = {r, r + 1, r + 1, r + 1};
            size_t q[4];
            float wsum = 0, wk[4];
            for (int k = 0; k < 4; ++k) {
                wk[k] = 0;
                if (nc[k] < 0 || nc[k] >= w || nr[k] >= h) continue;
                q[k] = (size_t)nr[k] * (size_t)w + (size_t)nc[k];
                if (!mask[q[k]]) continue;
                wk[k] = fs[k];
                wsum += fs[k];
            }
            float zshare = wsum > 0 ? CARRY_Z : 1.0f;
            for (int j = 0; j < m; ++j) next[(size_t)j * plane + p] += zshare * e[j];
            if (wsum > 0) {
                float s = (1.0f - CARRY_Z) / wsum;
                for (int k = 0; k < 4; ++k) {
                    if (wk[k] == 0) continue;
                    for (int j = 0; j < m; ++j) err[(size_t)j * plane + q[k]] += s * wk[k] * e[j];
                }
            }
        }
    }
    memset(err, 0, (size_t)m * plane * sizeof *err);
}

void hv_halftone_seed_error(float *err, int m, int w, int h, uint64_t seed, size_t block)
{
    size_t plane = (size_t)w * (size_t)h;
    uint64_t base = hv_hash64(seed ^ hv_hash64((uint64_t)block + 0x51ed));
    for (size_t p = 0; p < plane; ++p) {
        float u[HV_MAX_MATERIALS], mean = 0;
        uint64_t s = hv_hash64(base + p);
        for (int j = 0; j < m; ++j) {
            s = hv_hash64(s);
            u[j] = (float)((double)(s >> 11) * (1.0 / 9007199254740992.0));
            mean += u[j];
        }
        mean /= (float)m;
        for (int j = 0; j < m; ++j) err[(size_t)j * plane + p] = 0.25f * (u[j] - mean);
    }
}

/* The error a block inherits: seeded noise, then two passes over the block's first layer
 * (discarded) so the carried error is already in its steady state. Error diffusion keeps
 * error "in stock" (positive for rare materials waiting for their turn, negative for common
 * ones); dropping that stock at the end of a block and starting the next one empty would bias
 * every block towards the common materials. */
void hv_halftone_diffuse_start(const float *frac, int m, int w, int h, const uint8_t *mask,
                               float **err, float **next, uint64_t seed, size_t block, int serp,
                               uint8_t *scratch)
{
    size_t plane = (size_t)w * (size_t)h;
    uint64_t counts[HV_MAX_MATERIALS];
    hv_halftone_seed_error(*err, m, w, h, seed, block);
    memset(*next, 0, (size_t)m * plane * sizeof **next);
    for (int pass = 0; pass < 2; ++pass) {
        hv_halftone_diffuse(frac, m, w, h, mask, *err, *next, serp, scratch, counts, NULL);
        float *t = *err;
        *err = *next;
        *next = t;
    }
}
