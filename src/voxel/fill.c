/* src/voxel/fill.c - the interior of a voxelized mesh (Wu 2.1).
 * Flood: the outside is flooded from the grid border through non-surface voxels, row by row
 * with word-parallel run filling (6- or 26-connected moves, matching the surface's
 * separation); what the flood cannot reach is inside.
 * Vote (robust, for holes and flipped facets): along each axis, every triangle toggles the
 * first voxel past each of its crossings with a line of voxel centres (point-in-triangle with
 * edge functions evaluated in a canonical vertex order and ties broken by symbolic
 * perturbation, so a line through a shared edge or vertex, or grazing a face, is counted
 * consistently); a prefix XOR turns toggles into
 * crossing parity. Parity ignores orientation, so flipped facets change nothing. A closed
 * surface crosses every full line an even number of times: a line with odd parity passed
 * through a hole and is not heard; a voxel is inside when more of its even lines say inside
 * than outside. Voxels left undecided (every line odd, or a tie) get the generalized winding
 * number (Jacobson, Kavan, Sorkine-Hornung 2013) of the mesh at their centre, |w| > 1/2. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "voxel_internal.h"

/* ---- flood ----------------------------------------------------------------------------- */

static inline uint64_t rev64(uint64_t x)
{
    x = ((x >> 1) & 0x5555555555555555ull) | ((x & 0x5555555555555555ull) << 1);
    x = ((x >> 2) & 0x3333333333333333ull) | ((x & 0x3333333333333333ull) << 2);
    x = ((x >> 4) & 0x0F0F0F0F0F0F0F0Full) | ((x & 0x0F0F0F0F0F0F0F0Full) << 4);
    return __builtin_bswap64(x);
}

/* Grow the set bits of o over the runs of passable bits p that contain them: an addition
 * carries a seed through the run above it; the same on bit-reversed words fills below. */
static void expand_runs(uint64_t *o, const uint64_t *srow, const hv_bitgrid *g)
{
    int64_t W = g->words;
    uint64_t carry = 0;
    for (int64_t w = 0; w < W; ++w) {
        uint64_t p = ~srow[w] & hv_bitgrid_valid(g, w);
        uint64_t x = (o[w] | carry) & p;
        uint64_t up = (((p + x) ^ p) & p) | x;
        o[w] |= up;
        carry = up >> 63;
    }
    carry = 0;
    for (int64_t w = W - 1; w >= 0; --w) {
        uint64_t p = rev64(~srow[w] & hv_bitgrid_valid(g, w));
        uint64_t x = (rev64(o[w]) | carry) & p;
        uint64_t up = (((p + x) ^ p) & p) | x;
        o[w] |= rev64(up);
        carry = up >> 63;
    }
}

hv_status hv_fill_flood(const hv_bitgrid *S, hv_bitgrid *O, int adjacency,
                        const hv_progress *progress)
{
    int64_t nx = S->n[0], ny = S->n[1], W = S->words, nz = S->n[2];
    size_t rows = (size_t)(nx * ny);
    uint32_t *queue = hv_malloc_array(rows, sizeof *queue);
    uint8_t *inq = hv_calloc(rows, 1);
    uint64_t *seed = hv_malloc_array((size_t)W, sizeof *seed);
    if (!queue || !inq || !seed) {
        free(queue);
        free(inq);
        free(seed);
        return HV_ERR_NOMEM;
    }
    size_t head = 0, count = 0;
#define PUSH(r)                                        \
    do {                                               \
        if (!inq[r]) {                                 \
            inq[r] = 1;                                \
            queue[(head + count) % rows] = (uint32_t)(r); \
            ++count;                                   \
        }                                              \
    } while (0)
    /* seeds: the whole border of the grid that is not surface */
    for (int64_t i = 0; i < nx; ++i)
        for (int64_t j = 0; j < ny; ++j) {
            uint64_t *o = hv_bitgrid_row(O, i, j);
            const uint64_t *s = hv_bitgrid_row(S, i, j);
            int border = i == 0 || j == 0 || i == nx - 1 || j == ny - 1;
            int any = 0;
            if (border) {
                for (int64_t w = 0; w < W; ++w) o[w] = ~s[w] & hv_bitgrid_valid(S, w);
                any = 1;
            } else {
                o[0] |= ~s[0] & 1u;
                o[(nz - 1) >> 6] |= ~s[(nz - 1) >> 6] & (1ull << ((nz - 1) & 63));
                any = 1;
            }
            if (any) PUSH((size_t)(i * ny + j));
        }
    int adj26 = adjacency == 26;
    size_t processed = 0;
    hv_status st = HV_OK;
    while (count) {
        size_t r = queue[head];
        head = (head + 1) % rows;
        --count;
        inq[r] = 0;
        int64_t i = (int64_t)r / ny, j = (int64_t)r % ny;
        uint64_t *o = hv_bitgrid_row(O, i, j);
        expand_runs(o, hv_bitgrid_row(S, i, j), S);
        if (adj26) { /* z-diagonal moves: neighbours see this row dilated by one along z */
            for (int64_t w = 0; w < W; ++w)
                seed[w] = o[w] | (o[w] << 1) | (o[w] >> 1) | (w > 0 ? o[w - 1] >> 63 : 0) |
                          (w + 1 < W ? o[w + 1] << 63 : 0);
        } else {
            memcpy(seed, o, (size_t)W * sizeof *seed);
        }
        for (int di = -1; di <= 1; ++di)
            for (int dj = -1; dj <= 1; ++dj) {
                if (di == 0 && dj == 0) continue;
                if (!adj26 && di != 0 && dj != 0) continue;
                int64_t qi = i + di, qj = j + dj;
                if (qi < 0 || qj < 0 || qi >= nx || qj >= ny) continue;
                uint64_t *oq = hv_bitgrid_row(O, qi, qj);
                const uint64_t *sq = hv_bitgrid_row(S, qi, qj);
                /* a 6-connected move changes one coordinate: in-plane moves carry the row
                 * itself; with 26 both dilated along z and diagonal in-plane are allowed */
                const uint64_t *sd = adj26 ? seed : o;
                uint64_t any = 0;
                for (int64_t w = 0; w < W; ++w) {
                    uint64_t add = sd[w] & ~sq[w] & ~oq[w] & hv_bitgrid_valid(S, w);
                    oq[w] |= add;
                    any |= add;
                }
                if (any) PUSH((size_t)(qi * ny + qj));
            }
        if ((++processed & 8191) == 0 && progress && progress->fn) {
            st = hv_progress_report(progress, "interior", HV_MIN(0.99, (double)processed / (double)rows));
            if (st != HV_OK) break;
        }
    }
#undef PUSH
    free(queue);
    free(inq);
    free(seed);
    if (st != HV_OK) return st;
    /* inside = not reached by the flood (surface voxels included) */
    for (size_t r = 0; r < rows; ++r) {
        uint64_t *o = O->bits + r * (size_t)W;
        for (int64_t w = 0; w < W; ++w) o[w] = ~o[w] & hv_bitgrid_valid(S, w);
    }
    return hv_progress_report(progress, "interior", 1.0);
}

/* ---- vote ------------------------------------------------------------------------------ */

typedef struct vote_ctx {
    const hv_mesh *mesh;
    const double *P;
    hv_bitgrid *T; /* toggles, then parity (in place) */
    int axis;      /* the lines run along this axis */
} vote_ctx;

/* 2-D orientation of p relative to the directed segment a -> b. */
static inline double orient2(const double *a, const double *b, double px, double py)
{
    return (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
}

static void toggle(hv_bitgrid *T, int axis, int64_t line_u, int64_t line_v, int64_t k)
{
    int64_t q[3];
    q[axis] = k;
    q[(axis + 1) % 3] = line_u;
    q[(axis + 2) % 3] = line_v;
    __atomic_fetch_xor(&hv_bitgrid_row(T, q[0], q[1])[q[2] >> 6], 1ull << (q[2] & 63),
                       __ATOMIC_RELAXED);
}

static hv_status vote_range(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    vote_ctx *c = vctx;
    int a = c->axis, ua = (a + 1) % 3, va = (a + 2) % 3;
    const uint32_t *tri = hv_mesh_facets(c->mesh);
    int64_t na = c->T->n[a], nu = c->T->n[ua], nv = c->T->n[va];
    for (size_t f = b; f < e; ++f) {
        const uint32_t *t = tri + 3 * f;
        double q[3][2], h[3];
        for (int k = 0; k < 3; ++k) {
            const double *p = c->P + 3 * (size_t)t[k];
            q[k][0] = p[ua];
            q[k][1] = p[va];
            h[k] = p[a];
        }
        /* canonical edge data: edge k joins t[k] and t[(k+1)%3]; evaluate from the lower
         * vertex id so both triangles on an edge compute the very same number */
        const double *ea[3], *eb[3];
        int pos[3];
        int degenerate = 0;
        for (int k = 0; k < 3; ++k) {
            int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
            int lo = t[k] < t[k1] ? k : k1, hi = lo == k ? k1 : k;
            ea[k] = q[lo];
            eb[k] = q[hi];
            double side = orient2(ea[k], eb[k], q[k2][0], q[k2][1]);
            if (side == 0) degenerate = 1;
            pos[k] = side > 0;
        }
        if (degenerate) continue; /* parallel to the lines: no crossing */
        double area = orient2(q[0], q[1], q[2][0], q[2][1]);
        double u0 = ceil(HV_MIN(q[0][0], HV_MIN(q[1][0], q[2][0])));
        double u1 = floor(HV_MAX(q[0][0], HV_MAX(q[1][0], q[2][0])));
        double v0 = ceil(HV_MIN(q[0][1], HV_MIN(q[1][1], q[2][1])));
        double v1 = floor(HV_MAX(q[0][1], HV_MAX(q[1][1], q[2][1])));
        u0 = HV_MAX(u0, 0.0);
        v0 = HV_MAX(v0, 0.0);
        u1 = HV_MIN(u1, (double)(nu - 1));
        v1 = HV_MIN(v1, (double)(nv - 1));
        for (double u = u0; u <= u1; u += 1.0)
            for (double v = v0; v <= v1; v += 1.0) {
                int in = 1;
                for (int k = 0; k < 3 && in; ++k) {
                    double ev = orient2(ea[k], eb[k], u, v);
                    /* on the edge's line: decide as for the point moved by (e1, e2),
                     * 0 < e1 << e2 infinitesimal (simulation of simplicity); the sign
                     * depends on the edge alone, so every triangle decides alike even when
                     * the line grazes a face lying in the ray's plane */
                    if (ev == 0) ev = eb[k][0] != ea[k][0] ? eb[k][0] - ea[k][0] : ea[k][1] - eb[k][1];
                    in = pos[k] ? ev > 0 : ev < 0;
                }
                if (!in) continue;
                /* crossing height by barycentric interpolation */
                double l0 = orient2(q[1], q[2], u, v) / area, l1 = orient2(q[2], q[0], u, v) / area;
                double hh = l0 * h[0] + l1 * h[1] + (1.0 - l0 - l1) * h[2];
                double k = ceil(hh); /* first voxel centre at or above the crossing */
                if (k < 0) k = 0;
                if (k >= (double)na) continue;
                toggle(c->T, a, (int64_t)u, (int64_t)v, (int64_t)k);
            }
    }
    return HV_OK;
}

typedef struct prefix_ctx {
    hv_bitgrid *T;
    int axis;
} prefix_ctx;

/* Turn toggles into parity: prefix XOR along the axis. */
static hv_status prefix_range(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    prefix_ctx *c = vctx;
    hv_bitgrid *T = c->T;
    int64_t W = T->words;
    for (size_t s = b; s < e; ++s) {
        if (c->axis == 0) { /* s = j: rows (i, j) over i */
            for (int64_t i = 1; i < T->n[0]; ++i) {
                uint64_t *r = hv_bitgrid_row(T, i, (int64_t)s), *p = hv_bitgrid_row(T, i - 1, (int64_t)s);
                for (int64_t w = 0; w < W; ++w) r[w] ^= p[w];
            }
        } else if (c->axis == 1) { /* s = i: rows (i, j) over j */
            for (int64_t j = 1; j < T->n[1]; ++j) {
                uint64_t *r = hv_bitgrid_row(T, (int64_t)s, j), *p = hv_bitgrid_row(T, (int64_t)s, j - 1);
                for (int64_t w = 0; w < W; ++w) r[w] ^= p[w];
            }
        } else { /* s = row: bits along z */
            uint64_t *r = T->bits + s * (size_t)W, carry = 0;
            for (int64_t w = 0; w < W; ++w) {
                uint64_t x = r[w];
                x ^= x << 1;
                x ^= x << 2;
                x ^= x << 4;
                x ^= x << 8;
                x ^= x << 16;
                x ^= x << 32;
                x ^= carry;
                r[w] = x;
                carry = (x >> 63) ? ~0ull : 0ull;
            }
        }
    }
    return HV_OK;
}

/* ---- undecided voxels: the generalized winding number (Jacobson et al. 2013) --------------- */

typedef struct wind_ctx {
    const hv_mesh *mesh;
    const double *P;
    const int64_t *cells; /* (i, j, k) triples */
    uint8_t *inside;
} wind_ctx;

/* Sum of the signed solid angles of the facets seen from each cell centre, over 4 pi (Van
 * Oosterom & Strackee 1983): 1 inside a closed outward mesh, 0 outside; a hole only removes
 * its own solid angle, so |w| > 1/2 stays a sound inside test next to it. */
static hv_status wind_range(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    wind_ctx *c = vctx;
    const uint32_t *tri = hv_mesh_facets(c->mesh);
    size_t nf = hv_mesh_facet_count(c->mesh);
    for (size_t q = b; q < e; ++q) {
        double px = (double)c->cells[3 * q], py = (double)c->cells[3 * q + 1], pz = (double)c->cells[3 * q + 2];
        double sum = 0;
        for (size_t f = 0; f < nf; ++f) {
            const double *A = c->P + 3 * (size_t)tri[3 * f], *B = c->P + 3 * (size_t)tri[3 * f + 1],
                         *C = c->P + 3 * (size_t)tri[3 * f + 2];
            double ax = A[0] - px, ay = A[1] - py, az = A[2] - pz;
            double bx = B[0] - px, by = B[1] - py, bz = B[2] - pz;
            double cx = C[0] - px, cy = C[1] - py, cz = C[2] - pz;
            double la = sqrt(ax * ax + ay * ay + az * az), lb = sqrt(bx * bx + by * by + bz * bz),
                   lc = sqrt(cx * cx + cy * cy + cz * cz);
            double det = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
            double den = la * lb * lc + (ax * bx + ay * by + az * bz) * lc +
                         (ax * cx + ay * cy + az * cz) * lb + (bx * cx + by * cy + bz * cz) * la;
            sum += atan2(det, den);
        }
        c->inside[q] = fabs(sum) > M_PI; /* |w| = |sum| / (2 pi) > 1/2 */
    }
    return HV_OK;
}

/* At most this many facet-cell solid angles for the undecided voxels (a few seconds on two
 * cores); beyond it they keep the plain majority of the three parities. */
#define WIND_BUDGET 1.5e9

/* The vote on the lattice of G: occ = S | the voxels the vote puts inside; without S (NULL) every
 * voxel is decided by its centre alone (the undecided surface voxels too). */
static hv_status vote(const hv_mesh *mesh, const double *P, const hv_bitgrid *G, const hv_bitgrid *S, hv_bitgrid *occ,
                      const hv_progress *progress)
{
    hv_bitgrid T[3];
    memset(T, 0, sizeof T);
    hv_status st = HV_OK;
    for (int a = 0; a < 3 && st == HV_OK; ++a) st = hv_bitgrid_init(&T[a], G->n, G->lo);
    int64_t nx = G->n[0], ny = G->n[1], nz = G->n[2], W = G->words;
    size_t nwords = (size_t)(nx * ny * W);
    /* odd lines: a closed surface crosses every full line an even number of times, so a line
     * with odd parity passed through a hole and says nothing; x lines are indexed (j, k) and y
     * lines (i, k) as bit rows over k, z lines (i, j) one byte each */
    uint64_t *odd0 = hv_calloc((size_t)(ny * W), sizeof *odd0), *odd1 = hv_calloc((size_t)(nx * W), sizeof *odd1);
    uint8_t *odd2 = hv_calloc((size_t)(nx * ny), 1);
    if (st == HV_OK && (!odd0 || !odd1 || !odd2)) st = HV_ERR_NOMEM;
    for (int axis = 0; axis < 3 && st == HV_OK; ++axis) {
        vote_ctx vc = {mesh, P, &T[axis], axis};
        st = hv_parallel_for(hv_mesh_facet_count(mesh), 1024, vote_range, &vc, progress, "interior");
        if (st != HV_OK) break;
        prefix_ctx pc = {&T[axis], axis};
        size_t n = axis == 0 ? (size_t)ny : axis == 1 ? (size_t)nx : (size_t)(nx * ny);
        st = hv_parallel_for(n, axis == 2 ? 4096 : 8, prefix_range, &pc, NULL, "interior");
    }
    if (st == HV_OK) {
        for (int64_t j = 0; j < ny; ++j)
            memcpy(odd0 + j * W, hv_bitgrid_row(&T[0], nx - 1, j), (size_t)W * sizeof *odd0);
        for (int64_t i = 0; i < nx; ++i)
            memcpy(odd1 + i * W, hv_bitgrid_row(&T[1], i, ny - 1), (size_t)W * sizeof *odd1);
        for (int64_t i = 0; i < nx; ++i)
            for (int64_t j = 0; j < ny; ++j)
                odd2[i * ny + j] = (uint8_t)((hv_bitgrid_row(&T[2], i, j)[(nz - 1) >> 6] >> ((nz - 1) & 63)) & 1);
    }
    /* votes of the even lines only: inside when more of them say inside than outside; a tie
     * (no even line, or one each way) is undecided and left to the winding number */
    size_t nundecided = 0;
    if (st == HV_OK) {
        for (int64_t i = 0; i < nx; ++i)
            for (int64_t j = 0; j < ny; ++j) {
                uint64_t *p0 = hv_bitgrid_row(&T[0], i, j), *p1 = hv_bitgrid_row(&T[1], i, j);
                const uint64_t *p2 = hv_bitgrid_row(&T[2], i, j), *s = S ? hv_bitgrid_row(S, i, j) : NULL;
                uint64_t *o = hv_bitgrid_row(occ, i, j), r2 = odd2[i * ny + j] ? 0 : ~0ull;
                for (int64_t w = 0; w < W; ++w) {
                    uint64_t r0 = ~odd0[j * W + w], r1 = ~odd1[i * W + w];
                    uint64_t a = p0[w] & r0, b = p1[w] & r1, c = p2[w] & r2;
                    uint64_t x = ~p0[w] & r0, y = ~p1[w] & r1, z = ~p2[w] & r2;
                    uint64_t inL = a ^ b ^ c, inH = (a & b) | (a & c) | (b & c);
                    uint64_t outL = x ^ y ^ z, outH = (x & y) | (x & z) | (y & z);
                    uint64_t gt = (inH & ~outH) | (~(inH ^ outH) & inL & ~outL);
                    uint64_t eq = ~(inH ^ outH) & ~(inL ^ outL);
                    uint64_t valid = hv_bitgrid_valid(G, w), sw = s ? s[w] : 0;
                    o[w] = (gt | sw) & valid;
                    /* this word's parities are used up: T[0] keeps the undecided, T[1] the
                     * majority of all three lines (the fallback beyond the budget) */
                    uint64_t undecided = eq & ~sw & valid;
                    uint64_t maj = (p0[w] & p1[w]) | (p0[w] & p2[w]) | (p1[w] & p2[w]);
                    p0[w] = undecided;
                    p1[w] = maj;
                    nundecided += (size_t)__builtin_popcountll(undecided);
                }
            }
    }
    if (st == HV_OK && nundecided > 0) {
        /* the centres of an assembly's bodies (no S) never take the winding number: only an open
         * body leaves centres undecided, and next to an open surface w is close to 1/2 on both
         * sides, so the exact sum (the whole body's facets per voxel: 23 open groups of a 200,000
         * facet part took 44 times the part's time, issue 32 item 20) decides nothing the
         * lines' majority does not */
        if (S && (double)nundecided * (double)hv_mesh_facet_count(mesh) <= WIND_BUDGET) {
            int64_t *cells = hv_malloc_array(nundecided, 3 * sizeof *cells);
            uint8_t *inside = hv_malloc(nundecided);
            if (!cells || !inside) {
                st = HV_ERR_NOMEM;
            } else {
                size_t q = 0;
                for (int64_t i = 0; i < nx; ++i)
                    for (int64_t j = 0; j < ny; ++j)
                        for (int64_t w = 0; w < W; ++w)
                            for (uint64_t u = hv_bitgrid_row(&T[0], i, j)[w]; u; u &= u - 1) {
                                cells[3 * q] = i;
                                cells[3 * q + 1] = j;
                                cells[3 * q + 2] = 64 * w + __builtin_ctzll(u);
                                ++q;
                            }
                wind_ctx wc = {mesh, P, cells, inside};
                st = hv_parallel_for(nundecided, 16, wind_range, &wc, progress, "interior");
                for (size_t k = 0; st == HV_OK && k < nundecided; ++k)
                    if (inside[k]) {
                        int64_t kz = cells[3 * k + 2];
                        hv_bitgrid_row(occ, cells[3 * k], cells[3 * k + 1])[kz >> 6] |= 1ull << (kz & 63);
                    }
            }
            free(cells);
            free(inside);
        } else { /* too many for the winding number: the plain majority of the three lines */
            for (size_t w = 0; w < nwords; ++w) occ->bits[w] |= T[0].bits[w] & T[1].bits[w];
        }
    }
    for (int a = 0; a < 3; ++a) hv_bitgrid_free(&T[a]);
    free(odd0);
    free(odd1);
    free(odd2);
    return st;
}

hv_status hv_fill_vote(const hv_mesh *mesh, const double *P, const hv_bitgrid *S, hv_bitgrid *occ,
                       const hv_progress *progress)
{
    return vote(mesh, P, S, S, occ, progress);
}

hv_status hv_fill_centres(const hv_mesh *mesh, const double *P, hv_bitgrid *in, const hv_progress *progress)
{
    return vote(mesh, P, in, NULL, in, progress);
}
