/* src/field/harmonic.c - harmonic field between two labelled regions (the Laplace equation of
 * the non-manifold multi-material meshes seed, sec. 5: phi = 1 on one group, 0 on the other,
 * zero normal derivative elsewhere), finite differences on the voxel grid, solved by conjugate
 * gradients preconditioned with a cell-centred geometric multigrid V-cycle. */
#include <float.h>
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/field.h"

/* The discrete problem. Unknowns are the "free" voxels: domain voxels without label 1 or 2
 * that a 6-connected path through the domain joins to a labelled voxel. The masked 7-point
 * stencil couples two free face neighbours with weight 1/s_axis^2; a face towards a labelled
 * voxel adds its weight to the diagonal and weight * value to the right-hand side; faces
 * towards non-domain voxels are dropped (zero flux, a second-order Neumann condition on the
 * voxel faces). The matrix is a weighted graph Laplacian plus a non-negative diagonal that is
 * positive somewhere in every component: symmetric positive definite.
 *
 * The preconditioner. Level l+1 aggregates 2x2x2 cells of level l (clipped at odd sizes); a
 * coarse cell is free when a child is. Coarse operators are the Galerkin products P^T A P for
 * piecewise-constant P, halved: on a full aggregate this is exactly the rediscretised Laplacian
 * at twice the spacing (P^T A P is twice too stiff for constant interpolation), and near the
 * boundary each coarse face weighs the fine faces it covers, so the coarse problem sees the
 * true open area of thin passages. Every level is again "graph Laplacian + non-negative
 * diagonal", hence SPD. Smoothing is red-black Gauss-Seidel, red then black before the coarse
 * correction and black then red after, with restriction R = P^T: the V-cycle is then a
 * symmetric positive definite operator whatever the coarse operators are (the smoother
 * M satisfies M + M^T - A = D > 0), which is all CG needs. The coarsest level (at most 4 cells
 * per axis) gets a fixed number of symmetric sweeps, again SPD.
 *
 * Grids are stored dense with one cell of padding on every side, so stencils need no bounds
 * tests: non-free cells have zero weights and a zero inverse diagonal. The preconditioner works
 * in float (it only has to be a good approximation); CG itself runs in double. Every parallel
 * loop either writes disjoint cells or sums per x-plane into a fixed slot, so the result does
 * not depend on the thread count. */

enum { K_OUT = 0, K_FREE = 1, K_ONE = 2, K_ZERO = 3, K_CAND = 4 };

#define PRE_SWEEPS 2
#define COARSEST_SWEEPS 40
#define MAX_LEVELS 48
#define SERIAL_CELLS 16384 /* levels smaller than this run on one thread */

typedef struct level {
    int64_t nx, ny, nz;  /* interior cells */
    size_t sx, sy, n;    /* strides of the padded grid, padded cell count */
    float *wx, *wy, *wz; /* face weight between a cell and its +x/+y/+z neighbour */
    float *diag, *inv;   /* diagonal and its inverse (0 on non-free cells) */
    float *d0;           /* coupling to labelled voxels (setup only) */
    float *x, *b, *r;    /* correction, right-hand side, residual */
} level;

typedef struct solver {
    level lv[MAX_LEVELS];
    int nlev;
    int threads;
    double *part; /* per-plane partial sums (fine nx entries) */
    double *d0;   /* fine level: coupling to labelled voxels, exact (CG's operator) */
} solver;

static inline size_t at(const level *L, int64_t i, int64_t j, int64_t k)
{
    return (size_t)(i + 1) * L->sx + (size_t)(j + 1) * L->sy + (size_t)(k + 1);
}

static int par(const level *L) { return (size_t)(L->nx * L->ny * L->nz) > SERIAL_CELLS; }

/* ---- multigrid ---------------------------------------------------------------------------- */

/* One colour of Gauss-Seidel: cells with (i + j + k) % 2 == colour. */
static void smooth(const solver *S, const level *L, int colour)
{
    const float *wx = L->wx, *wy = L->wy, *wz = L->wz, *inv = L->inv, *b = L->b;
    float *x = L->x;
    const size_t sx = L->sx, sy = L->sy;
#pragma omp parallel for schedule(static) num_threads(S->threads) if (par(L))
    for (int64_t i = 0; i < L->nx; ++i)
        for (int64_t j = 0; j < L->ny; ++j) {
            int64_t k0 = (i + j + colour) & 1;
            size_t c = at(L, i, j, k0);
            for (int64_t k = k0; k < L->nz; k += 2, c += 2) {
                float s = b[c] + wx[c] * x[c + sx] + wx[c - sx] * x[c - sx] + wy[c] * x[c + sy] +
                          wy[c - sy] * x[c - sy] + wz[c] * x[c + 1] + wz[c - 1] * x[c - 1];
                x[c] = s * inv[c];
            }
        }
}

static void residual(const solver *S, const level *L)
{
    const float *wx = L->wx, *wy = L->wy, *wz = L->wz, *diag = L->diag, *b = L->b, *x = L->x;
    float *r = L->r;
    const size_t sx = L->sx, sy = L->sy;
#pragma omp parallel for schedule(static) num_threads(S->threads) if (par(L))
    for (int64_t i = 0; i < L->nx; ++i)
        for (int64_t j = 0; j < L->ny; ++j) {
            size_t c = at(L, i, j, 0);
            for (int64_t k = 0; k < L->nz; ++k, ++c)
                r[c] = b[c] - diag[c] * x[c] + wx[c] * x[c + sx] + wx[c - sx] * x[c - sx] +
                       wy[c] * x[c + sy] + wy[c - sy] * x[c - sy] + wz[c] * x[c + 1] +
                       wz[c - 1] * x[c - 1];
        }
}

/* b of level C = P^T r of level F (sum over the children; padding children hold 0). */
static void restrict_to(const solver *S, const level *F, const level *C)
{
    const float *r = F->r;
    float *b = C->b;
    const size_t fx = F->sx, fy = F->sy;
#pragma omp parallel for schedule(static) num_threads(S->threads) if (par(C))
    for (int64_t i = 0; i < C->nx; ++i)
        for (int64_t j = 0; j < C->ny; ++j)
            for (int64_t k = 0; k < C->nz; ++k) {
                size_t f = at(F, 2 * i, 2 * j, 2 * k);
                b[at(C, i, j, k)] = (r[f] + r[f + 1] + r[f + fy] + r[f + fy + 1]) +
                                    (r[f + fx] + r[f + fx + 1] + r[f + fx + fy] + r[f + fx + fy + 1]);
            }
}

/* x of level F += P x of level C on free cells. */
static void prolong_add(const solver *S, const level *F, const level *C)
{
    const float *xc = C->x, *inv = F->inv;
    float *x = F->x;
#pragma omp parallel for schedule(static) num_threads(S->threads) if (par(F))
    for (int64_t i = 0; i < F->nx; ++i)
        for (int64_t j = 0; j < F->ny; ++j) {
            size_t c = at(F, i, j, 0), pc = at(C, i / 2, j / 2, 0);
            for (int64_t k = 0; k < F->nz; ++k, ++c)
                if (inv[c] != 0.0f) x[c] += xc[pc + (size_t)(k / 2)];
        }
}

static void zero(const solver *S, const level *L)
{
    (void)S;
    memset(L->x, 0, L->n * sizeof(float));
}

/* x = V-cycle(b) on level l, from a zero initial guess. */
static void vcycle(const solver *S, int l)
{
    const level *L = &S->lv[l];
    zero(S, L);
    if (l == S->nlev - 1) {
        /* red (black red)^m: a palindrome of sweeps, so symmetric */
        smooth(S, L, 0);
        for (int s = 0; s < COARSEST_SWEEPS; ++s) {
            smooth(S, L, 1);
            smooth(S, L, 0);
        }
        return;
    }
    for (int s = 0; s < PRE_SWEEPS; ++s) {
        smooth(S, L, 0);
        smooth(S, L, 1);
    }
    residual(S, L);
    restrict_to(S, L, &S->lv[l + 1]);
    vcycle(S, l + 1);
    prolong_add(S, L, &S->lv[l + 1]);
    for (int s = 0; s < PRE_SWEEPS; ++s) {
        smooth(S, L, 1);
        smooth(S, L, 0);
    }
}

/* ---- setup ---------------------------------------------------------------------------------- */

static hv_status level_alloc(level *L, int64_t nx, int64_t ny, int64_t nz)
{
    L->nx = nx;
    L->ny = ny;
    L->nz = nz;
    L->sy = (size_t)nz + 2;
    L->sx = L->sy * ((size_t)ny + 2);
    L->n = L->sx * ((size_t)nx + 2);
    float **arr[] = {&L->wx, &L->wy, &L->wz, &L->diag, &L->inv, &L->d0, &L->x, &L->b, &L->r};
    for (size_t a = 0; a < HV_COUNT(arr); ++a) {
        *arr[a] = hv_calloc(L->n, sizeof(float));
        if (!*arr[a]) return HV_ERR_NOMEM;
    }
    return HV_OK;
}

static void level_free(level *L)
{
    float *arr[] = {L->wx, L->wy, L->wz, L->diag, L->inv, L->d0, L->x, L->b, L->r};
    for (size_t a = 0; a < HV_COUNT(arr); ++a) free(arr[a]);
}

/* Diagonal and inverse from the face weights and d0. */
static void finish_level(const solver *S, level *L)
{
    const size_t sx = L->sx, sy = L->sy;
#pragma omp parallel for schedule(static) num_threads(S->threads) if (par(L))
    for (int64_t i = 0; i < L->nx; ++i)
        for (int64_t j = 0; j < L->ny; ++j) {
            size_t c = at(L, i, j, 0);
            for (int64_t k = 0; k < L->nz; ++k, ++c) {
                float d = L->d0[c] + L->wx[c] + L->wx[c - sx] + L->wy[c] + L->wy[c - sy] +
                          L->wz[c] + L->wz[c - 1];
                L->diag[c] = d;
                L->inv[c] = d > 0 ? 1.0f / d : 0.0f;
            }
        }
}

/* Level C from level F: halved Galerkin weights of the fine faces each coarse face covers. */
static void coarsen(const solver *S, const level *F, level *C)
{
    const size_t fx = F->sx, fy = F->sy;
#pragma omp parallel for schedule(static) num_threads(S->threads) if (par(C))
    for (int64_t i = 0; i < C->nx; ++i)
        for (int64_t j = 0; j < C->ny; ++j)
            for (int64_t k = 0; k < C->nz; ++k) {
                size_t f = at(F, 2 * i, 2 * j, 2 * k), c = at(C, i, j, k);
                /* faces between child layer 1 of this cell and layer 0 of the next; where the
                 * fine grid ends those children are padding with zero weights */
                float wx = F->wx[f + fx] + F->wx[f + fx + 1] + F->wx[f + fx + fy] +
                           F->wx[f + fx + fy + 1];
                float wy = F->wy[f + fy] + F->wy[f + fy + 1] + F->wy[f + fy + fx] +
                           F->wy[f + fy + fx + 1];
                float wz = F->wz[f + 1] + F->wz[f + 1 + fy] + F->wz[f + 1 + fx] +
                           F->wz[f + 1 + fx + fy];
                float d0 = F->d0[f] + F->d0[f + 1] + F->d0[f + fy] + F->d0[f + fy + 1] +
                           F->d0[f + fx] + F->d0[f + fx + 1] + F->d0[f + fx + fy] +
                           F->d0[f + fx + fy + 1];
                /* the last coarse cell of an axis has no +neighbour */
                C->wx[c] = i + 1 < C->nx ? 0.5f * wx : 0.0f;
                C->wy[c] = j + 1 < C->ny ? 0.5f * wy : 0.0f;
                C->wz[c] = k + 1 < C->nz ? 0.5f * wz : 0.0f;
                C->d0[c] = 0.5f * d0;
            }
}

static void solver_free(solver *S)
{
    for (int l = 0; l < S->nlev; ++l) level_free(&S->lv[l]);
    free(S->part);
    free(S->d0);
}

/* ---- CG vector kernels (double, fine level; sums per x-plane, added in order) --------------- */

static double plane_sum(const solver *S, int64_t nx)
{
    double s = 0;
    for (int64_t i = 0; i < nx; ++i) s += S->part[i];
    return s;
}

/* q = A p, returns p.q. Written as d0 p + sum of w (p - p_neighbour), in double, so that the
 * operator annihilates constants exactly away from the labels (a diagonal rounded to float
 * would act as a spurious sink of relative size 1e-7, visible as a 1e-4 bow in a bar). */
static double matvec_dot(const solver *S, const double *p, double *q)
{
    const level *L = &S->lv[0];
    const float *wx = L->wx, *wy = L->wy, *wz = L->wz;
    const double *d0 = S->d0;
    const size_t sx = L->sx, sy = L->sy;
#pragma omp parallel for schedule(static) num_threads(S->threads)
    for (int64_t i = 0; i < L->nx; ++i) {
        double s = 0;
        for (int64_t j = 0; j < L->ny; ++j) {
            size_t c = at(L, i, j, 0);
            for (int64_t k = 0; k < L->nz; ++k, ++c) {
                double pc = p[c];
                double v = d0[c] * pc + ((double)wx[c] * (pc - p[c + sx]) +
                                         (double)wx[c - sx] * (pc - p[c - sx]) +
                                         (double)wy[c] * (pc - p[c + sy]) +
                                         (double)wy[c - sy] * (pc - p[c - sy]) +
                                         (double)wz[c] * (pc - p[c + 1]) +
                                         (double)wz[c - 1] * (pc - p[c - 1]));
                q[c] = v;
                s += v * p[c];
            }
        }
        S->part[i] = s;
    }
    return plane_sum(S, L->nx);
}

/* x += a p, r -= a q, returns r.r */
static double update_xr(const solver *S, double a, const double *p, const double *q, double *x,
                        double *r)
{
    const level *L = &S->lv[0];
#pragma omp parallel for schedule(static) num_threads(S->threads)
    for (int64_t i = 0; i < L->nx; ++i) {
        double s = 0;
        for (int64_t j = 0; j < L->ny; ++j) {
            size_t c = at(L, i, j, 0);
            for (int64_t k = 0; k < L->nz; ++k, ++c) {
                x[c] += a * p[c];
                double v = r[c] - a * q[c];
                r[c] = v;
                s += v * v;
            }
        }
        S->part[i] = s;
    }
    return plane_sum(S, L->nx);
}

/* z = M r (the V-cycle), returns r.z */
static double precondition(solver *S, const double *r, double *z)
{
    level *L = &S->lv[0];
#pragma omp parallel for schedule(static) num_threads(S->threads)
    for (int64_t i = 0; i < L->nx; ++i)
        for (int64_t j = 0; j < L->ny; ++j) {
            size_t c = at(L, i, j, 0);
            for (int64_t k = 0; k < L->nz; ++k, ++c) L->b[c] = (float)r[c];
        }
    vcycle(S, 0);
#pragma omp parallel for schedule(static) num_threads(S->threads)
    for (int64_t i = 0; i < L->nx; ++i) {
        double s = 0;
        for (int64_t j = 0; j < L->ny; ++j) {
            size_t c = at(L, i, j, 0);
            for (int64_t k = 0; k < L->nz; ++k, ++c) {
                double v = (double)L->x[c];
                z[c] = v;
                s += v * r[c];
            }
        }
        S->part[i] = s;
    }
    return plane_sum(S, L->nx);
}

/* p = z + beta p */
static void update_p(const solver *S, double beta, const double *z, double *p)
{
    const level *L = &S->lv[0];
#pragma omp parallel for schedule(static) num_threads(S->threads)
    for (int64_t i = 0; i < L->nx; ++i)
        for (int64_t j = 0; j < L->ny; ++j) {
            size_t c = at(L, i, j, 0);
            for (int64_t k = 0; k < L->nz; ++k, ++c) p[c] = z[c] + beta * p[c];
        }
}

/* ---- entry point ---------------------------------------------------------------------------- */

/* Mark the free voxels: breadth-first from every labelled voxel through the domain; domain
 * voxels never reached are floating. Returns their count. */
static uint64_t find_free(uint8_t *kind, size_t *queue, const level *L)
{
    size_t head = 0, tail = 0;
    for (size_t c = 0; c < L->n; ++c)
        if (kind[c] == K_ONE || kind[c] == K_ZERO) queue[tail++] = c;
    const size_t step[6] = {1, L->sy, L->sx, (size_t)-1, (size_t)0 - L->sy, (size_t)0 - L->sx};
    while (head < tail) {
        size_t c = queue[head++];
        for (int d = 0; d < 6; ++d) {
            size_t nb = c + step[d];
            if (kind[nb] == K_CAND) {
                kind[nb] = K_FREE;
                queue[tail++] = nb;
            }
        }
    }
    uint64_t floating = 0;
    for (size_t c = 0; c < L->n; ++c)
        if (kind[c] == K_CAND) {
            kind[c] = K_OUT;
            ++floating;
        }
    return floating;
}

/* The arguments' checks, before any allocation. */
static hv_status check_args(const uint8_t *domain, const uint8_t *label, const int64_t dims[3],
                            const double spacing[3], double tol, int max_iter, const float *phi)
{
    if (!domain || !label || !dims || !spacing || !phi)
        return hv_error_set(HV_ERR_INVALID, "harmonic: %s is NULL",
                            !domain  ? "domain"
                            : !label ? "label"
                            : !dims  ? "dims"
                            : !spacing ? "spacing"
                                       : "phi");
    static const char axis[3] = {'x', 'y', 'z'};
    for (int a = 0; a < 3; ++a) {
        if (dims[a] < 1)
            return hv_error_set(HV_ERR_INVALID, "harmonic: dimension %c must be >= 1 (got %lld)",
                                axis[a], (long long)dims[a]);
        if (!(isfinite(spacing[a]) && spacing[a] > 0))
            return hv_error_set(HV_ERR_INVALID,
                                "harmonic: spacing %c must be finite and > 0 (got %g)", axis[a],
                                spacing[a]);
        double wa = 1.0 / (spacing[a] * spacing[a]); /* the stencil weight, kept as a float */
        if (!(wa >= FLT_MIN && wa <= FLT_MAX))
            return hv_error_set(HV_ERR_INVALID,
                                "harmonic: spacing %c out of range for float weights (got %g)",
                                axis[a], spacing[a]);
    }
    if (!(tol > 0 && tol < 1))
        return hv_error_set(HV_ERR_INVALID, "harmonic: tolerance must be in (0, 1) (got %g)", tol);
    if (max_iter < 1)
        return hv_error_set(HV_ERR_INVALID, "harmonic: max_iter must be >= 1 (got %d)", max_iter);
    const int64_t limit = (int64_t)1 << 40;
    if (dims[0] > limit || dims[1] > limit / dims[0] || dims[2] > limit / (dims[0] * dims[1]))
        return hv_error_set(HV_ERR_LIMIT,
                            "harmonic: %lld x %lld x %lld voxels exceed the limit of 2^40",
                            (long long)dims[0], (long long)dims[1], (long long)dims[2]);
    /* labels too: a missing one is the caller's error */
    const size_t nvox = (size_t)(dims[0] * dims[1] * dims[2]);
    int has1 = 0, has2 = 0;
    for (size_t v = 0; v < nvox && !(has1 && has2); ++v)
        if (domain[v]) {
            has1 |= label[v] == 1;
            has2 |= label[v] == 2;
        }
    if (!has1 || !has2)
        return hv_error_set(HV_ERR_INVALID, "harmonic: no domain voxel is labelled %d", has1 ? 2 : 1);
    return HV_OK;
}

/* The level hierarchy, down to at most 4 cells per axis. */
static hv_status build_levels(solver *S, int64_t lx, int64_t ly, int64_t lz)
{
    for (;;) {
        hv_status st = HV_OK;
        if (S->nlev == MAX_LEVELS || (st = level_alloc(&S->lv[S->nlev], lx, ly, lz)) != HV_OK) {
            if (st == HV_OK) st = hv_error_set(HV_ERR_INTERNAL, "harmonic: too many levels");
            ++S->nlev; /* so solver_free releases a partly allocated level */
            return st;
        }
        ++S->nlev;
        if (lx <= 4 && ly <= 4 && lz <= 4) return HV_OK;
        lx = (lx + 1) / 2;
        ly = (ly + 1) / 2;
        lz = (lz + 1) / 2;
    }
}

/* Classify every voxel (outside, labelled 1 or 2, candidate), then find the free ones; the
 * count of floating domain voxels goes to *nfloat. */
static hv_status classify(const uint8_t *domain, const uint8_t *label, const level *F,
                          int64_t nx, int64_t ny, int64_t nz, uint8_t *kind, uint64_t *nfloat)
{
    size_t ncand = 0;
    for (int64_t i = 0; i < nx; ++i)
        for (int64_t j = 0; j < ny; ++j)
            for (int64_t k = 0; k < nz; ++k) {
                size_t v = (size_t)((i * ny + j) * nz + k);
                uint8_t t = K_OUT;
                if (domain[v]) t = label[v] == 1 ? K_ONE : label[v] == 2 ? K_ZERO : K_CAND;
                ncand += t != K_OUT;
                kind[at(F, i, j, k)] = t;
            }
    size_t *queue = hv_malloc_array(ncand, sizeof(size_t));
    if (!queue) return HV_ERR_NOMEM; /* ncand <= 2^40: no overflow, so out of memory */
    *nfloat = find_free(kind, queue, F);
    free(queue);
    return HV_OK;
}

/* The fine operator and the right-hand side b, into r (CG's r starts as b, x as 0); returns
 * |b|^2. The weights are rounded to float once; everything (d0, b, the matrix) uses these
 * values, so the discrete problem is exactly the masked Laplacian with these weights. */
static double assemble(solver *S, const uint8_t *kind, const double spacing[3], double *r)
{
    level *F = &S->lv[0];
    const double w[3] = {(float)(1.0 / (spacing[0] * spacing[0])),
                         (float)(1.0 / (spacing[1] * spacing[1])),
                         (float)(1.0 / (spacing[2] * spacing[2]))};
    const size_t step[3] = {F->sx, F->sy, 1};
    double bnorm2 = 0;
    for (int64_t i = 0; i < F->nx; ++i) {
        double s = 0;
        for (int64_t j = 0; j < F->ny; ++j) {
            size_t c = at(F, i, j, 0);
            for (int64_t k = 0; k < F->nz; ++k, ++c) {
                if (kind[c] != K_FREE) continue;
                float *wf[3] = {&F->wx[c], &F->wy[c], &F->wz[c]};
                double d0 = 0, b = 0;
                for (int a = 0; a < 3; ++a) {
                    uint8_t up = kind[c + step[a]], dn = kind[c - step[a]];
                    if (up == K_FREE) *wf[a] = (float)w[a];
                    d0 += (up == K_ONE || up == K_ZERO ? w[a] : 0) +
                          (dn == K_ONE || dn == K_ZERO ? w[a] : 0);
                    b += (up == K_ONE ? w[a] : 0) + (dn == K_ONE ? w[a] : 0);
                }
                S->d0[c] = d0;
                F->d0[c] = (float)d0;
                r[c] = b;
                s += b * b;
            }
        }
        bnorm2 += s;
    }
    return bnorm2;
}

/* Preconditioned conjugate gradients from x = 0, r = b, until |r| <= tol |b|; *iterations
 * receives the count. HV_ERR_LIMIT when it does not converge (x holds the last iterate). */
static hv_status pcg(solver *S, double bnorm2, double tol, int max_iter, double *x, double *r,
                     double *p, double *q, double *z, int *iterations, const hv_progress *progress)
{
    const level *F = &S->lv[0];
    const double bnorm = sqrt(bnorm2), target = tol * bnorm;
    double rnorm = bnorm;
    hv_status st = HV_OK;
    int it = 0;
    if (bnorm > 0) {
        double rz = precondition(S, r, z);
        memcpy(p, z, F->n * sizeof(double));
        while (rnorm > target) {
            if (it == max_iter) {
                st = hv_error_set(HV_ERR_LIMIT,
                                  "harmonic: no convergence in %d iterations (relative residual "
                                  "%.3g, tolerance %g)",
                                  max_iter, rnorm / bnorm, tol);
                break;
            }
            double pq = matvec_dot(S, p, q);
            if (!(pq > 0) || !(rz > 0)) {
                st = hv_error_set(HV_ERR_LIMIT,
                                  "harmonic: stalled after %d iterations (relative residual %.3g, "
                                  "tolerance %g)",
                                  it, rnorm / bnorm, tol);
                break;
            }
            double alpha = rz / pq;
            rnorm = sqrt(update_xr(S, alpha, p, q, x, r));
            ++it;
            double frac = rnorm > 0 ? log(rnorm / bnorm) / log(tol) : 1.0;
            if ((st = hv_progress_report(progress, "harmonic", frac)) != HV_OK) break;
            if (rnorm <= target) break;
            double rz_new = precondition(S, r, z);
            update_p(S, rz_new / rz, z, p);
            rz = rz_new;
        }
    }
    *iterations = it;
    return st;
}

/* phi: the iterate on free voxels (clamped to [0,1], which the exact solution obeys by the
 * maximum principle), the labels' values, 0 elsewhere. */
static void write_phi(const solver *S, const uint8_t *kind, const double *x, float *phi)
{
    const level *F = &S->lv[0];
    const int64_t nx = F->nx, ny = F->ny, nz = F->nz;
#pragma omp parallel for schedule(static) num_threads(S->threads)
    for (int64_t i = 0; i < nx; ++i)
        for (int64_t j = 0; j < ny; ++j) {
            size_t c = at(F, i, j, 0), v = (size_t)((i * ny + j) * nz);
            for (int64_t k = 0; k < nz; ++k, ++c, ++v) {
                float val = 0.0f;
                if (kind[c] == K_FREE) val = (float)HV_CLAMP(x[c], 0.0, 1.0);
                else if (kind[c] == K_ONE) val = 1.0f;
                phi[v] = val;
            }
        }
}

hv_status hv_harmonic(const uint8_t *domain, const uint8_t *label, const int64_t dims[3],
                      const double spacing[3], double tol, int max_iter, float *phi,
                      int *iterations, uint64_t *floating, const hv_progress *progress)
{
    if (iterations) *iterations = 0;
    if (floating) *floating = 0;
    hv_status st = check_args(domain, label, dims, spacing, tol, max_iter, phi);
    if (st != HV_OK) return st;
    const int64_t nx = dims[0], ny = dims[1], nz = dims[2];

    solver S;
    memset(&S, 0, sizeof S);
    S.threads = hv_threads();
    uint8_t *kind = NULL;
    double *x = NULL, *r = NULL, *p = NULL, *q = NULL, *z = NULL;
    if ((st = build_levels(&S, nx, ny, nz)) != HV_OK) goto done;
    level *F = &S.lv[0];
    S.part = hv_calloc((size_t)nx, sizeof(double));
    S.d0 = hv_calloc(F->n, sizeof(double));
    kind = hv_calloc(F->n, 1);
    x = hv_calloc(F->n, sizeof(double));
    r = hv_calloc(F->n, sizeof(double));
    p = hv_calloc(F->n, sizeof(double));
    q = hv_calloc(F->n, sizeof(double));
    z = hv_calloc(F->n, sizeof(double));
    if (!S.part || !S.d0 || !kind || !x || !r || !p || !q || !z) {
        st = HV_ERR_NOMEM;
        goto done;
    }
    uint64_t nfloat = 0;
    if ((st = classify(domain, label, F, nx, ny, nz, kind, &nfloat)) != HV_OK) goto done;
    if (floating) *floating = nfloat;
    if ((st = hv_progress_report(progress, "harmonic: setup", 0.0)) != HV_OK) goto done;

    double bnorm2 = assemble(&S, kind, spacing, r);
    finish_level(&S, F);
    for (int l = 1; l < S.nlev; ++l) {
        coarsen(&S, &S.lv[l - 1], &S.lv[l]);
        finish_level(&S, &S.lv[l]);
    }
    int it = 0;
    st = pcg(&S, bnorm2, tol, max_iter, x, r, p, q, z, &it, progress);
    if (iterations) *iterations = it;
    if (st != HV_OK && st != HV_ERR_LIMIT) goto done;
    write_phi(&S, kind, x, phi);

done:
    solver_free(&S);
    free(kind);
    free(x);
    free(r);
    free(p);
    free(q);
    free(z);
    return st;
}
