/* slicing/contours.c - contour loops of one plane by traversing the weighted directed graph
 * (Wu 2.4.1): one intersection per facet, loops in order without sorting segments; then the
 * gap rule for open meshes, orientation and nesting; and the multi-threaded batch over a plan. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "slice_internal.h"

struct hv_slice {
    hv_slice_stats stats;
    size_t nloops;
    hv_slice_loop *loops;
    double *xy;
};

void hv_slice_destroy(hv_slice *sl)
{
    if (!sl) return;
    free(sl->loops);
    free(sl->xy);
    free(sl);
}

size_t hv_slice_loop_count(const hv_slice *sl) { return sl ? sl->nloops : 0; }
const hv_slice_loop *hv_slice_loops(const hv_slice *sl) { return sl ? sl->loops : NULL; }
const hv_slice_stats *hv_slice_get_stats(const hv_slice *sl) { return sl ? &sl->stats : NULL; }

/* ---- per-plane work state ------------------------------------------------------------------- */

/* A traced chain: forward points in `fw` (off, n), and for open chains the points traced
 * backwards from the start in `bw` (boff, bn), which come first, reversed. Gap joining links
 * chains through `next`. */
typedef struct chain {
    size_t off, n, boff, bn;
    int closed;  /* closed by traversal, or by the gap rule (head chains) */
    int next;    /* next chain joined after this one, -1 */
    int tail;    /* head chains: last chain of the list */
    int absorbed; /* joined after another chain */
    int gaps;
    int body;    /* the mesh body of its facets */
    double vote; /* see facet_vote: > 0 when the facets put the material left of the chain */
} chain;

typedef struct work {
    const hv_slicer *s;
    double h;
    uint32_t *cross, *tmp; /* crossing facets, sorted */
    size_t ncross, cap_cross, cap_tmp;
    uint32_t *hkey, *hval; /* facet -> slot */
    size_t hmask;
    int hbits;
    uint8_t *visited;
    double *fw, *bw; /* point pairs */
    size_t nfw, nbw, cap_fw, cap_bw;
    chain *chains;
    size_t nchains, cap_chains;
} work;

static void work_free(work *w)
{
    free(w->cross);
    free(w->tmp);
    free(w->hkey);
    free(w->hval);
    free(w->visited);
    free(w->fw);
    free(w->bw);
    free(w->chains);
}

/* LSD radix sort of facet indices (< 2^31), 3 passes of 11 bits. */
static void sort_u32(uint32_t *a, uint32_t *tmp, size_t n)
{
    if (n < 64) {
        for (size_t i = 1; i < n; ++i) {
            uint32_t x = a[i];
            size_t j = i;
            for (; j > 0 && a[j - 1] > x; --j) a[j] = a[j - 1];
            a[j] = x;
        }
        return;
    }
    uint32_t *src = a, *dst = tmp;
    for (int pass = 0; pass < 3; ++pass) {
        int sh = 11 * pass;
        size_t cnt[2048] = {0};
        for (size_t i = 0; i < n; ++i) ++cnt[(src[i] >> sh) & 2047];
        size_t sum = 0;
        for (int d = 0; d < 2048; ++d) {
            size_t c = cnt[d];
            cnt[d] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; ++i) dst[cnt[(src[i] >> sh) & 2047]++] = src[i];
        uint32_t *t = src;
        src = dst;
        dst = t;
    }
    if (src != a) memcpy(a, src, n * sizeof *a);
}

static inline size_t hslot(const work *w, uint32_t f)
{
    return (size_t)((f * 2654435761u) >> (32 - w->hbits)) & w->hmask;
}

static long lookup(const work *w, uint32_t f)
{
    for (size_t i = hslot(w, f);; i = (i + 1) & w->hmask) {
        if (w->hkey[i] == f) return (long)w->hval[i];
        if (w->hkey[i] == UINT32_MAX) return -1;
    }
}

static hv_status push_point(double **buf, size_t *n, size_t *cap, const double p[2])
{
    if (*n + 1 > *cap && hv_grow((void **)buf, cap, *n + 1, 2 * sizeof **buf) != HV_OK)
        return HV_ERR_NOMEM;
    (*buf)[2 * *n] = p[0];
    (*buf)[2 * *n + 1] = p[1];
    ++*n;
    return HV_OK;
}

/* Below/above classification of facet f (symbolic perturbation: z >= h is above). Bit i set
 * when vertex i is below. */
static inline unsigned below_mask(const hv_slicer *s, uint32_t f, double h)
{
    const uint32_t *v = s->tri + 3 * (size_t)f;
    return (unsigned)(s->xyz[3 * (size_t)v[0] + 2] < h) |
           (unsigned)(s->xyz[3 * (size_t)v[1] + 2] < h) << 1 |
           (unsigned)(s->xyz[3 * (size_t)v[2] + 2] < h) << 2;
}

/* Is the edge of weight w crossed? It joins the two vertices other than 3 - w. */
static inline int crossed(unsigned below, int w)
{
    int o = 3 - w, a = o == 0 ? 1 : 0, b = o == 2 ? 1 : 2;
    return ((below >> a) & 1) != ((below >> b) & 1);
}

/* The crossed edge of weight other than w (0 when none). */
static inline int other_crossed(unsigned below, int w)
{
    for (int u = 1; u <= 3; ++u)
        if (u != w && crossed(below, u)) return u;
    return 0;
}

/* The crossing on edge w of facet f, computed from the below vertex to the above one so both
 * facets sharing the edge get bit-identical points. */
static inline void edge_point(const hv_slicer *s, uint32_t f, int w, double h, double p[2])
{
    int o = 3 - w, ia = o == 0 ? 1 : 0, ib = o == 2 ? 1 : 2;
    const double *a = s->xyz + 3 * (size_t)s->tri[3 * (size_t)f + (size_t)ia];
    const double *b = s->xyz + 3 * (size_t)s->tri[3 * (size_t)f + (size_t)ib];
    if (a[2] >= h) { /* make a the below vertex */
        const double *t = a;
        a = b;
        b = t;
    }
    /* (1 - t) a + t b is exact at t = 1, so a vertex lying on the plane yields its own
     * coordinates from every edge that ends there and the repeats can be dropped exactly */
    double t = (h - a[2]) / (b[2] - a[2]), u = 1.0 - t;
    p[0] = u * a[0] + t * b[0];
    p[1] = u * a[1] + t * b[1];
}

/* The start facet's exit: the edge its winding (v0 -> v1 -> v2) crosses upwards, so loops of
 * a consistently oriented closed mesh come out counter-clockwise around solid material. */
static int up_edge(unsigned below)
{
    static const int from[3] = {0, 1, 2}, to[3] = {1, 2, 0}, weight[3] = {1, 3, 2};
    for (int e = 0; e < 3; ++e)
        if (((below >> from[e]) & 1) && !((below >> to[e]) & 1)) return weight[e];
    return 0;
}

/* How far the segment a -> b, lying in facet f, agrees with f's outward normal: the length of
 * the segment times the cosine between the facet's horizontal normal and the segment's right
 * hand (y, -x). Summed over a loop, > 0 means the facets put the material on the left, so the
 * loop runs counter-clockwise round solid and clockwise round a cavity. A minority of flipped
 * facets cannot overturn it. */
static inline double facet_vote(const hv_slicer *s, uint32_t f, const double a[2],
                                const double b[2])
{
    double nx = (double)s->nxy[2 * (size_t)f], ny = (double)s->nxy[2 * (size_t)f + 1];
    return (b[1] - a[1]) * nx - (b[0] - a[0]) * ny;
}

/* Trace the chain through crossing slot i0. */
static hv_status trace(work *w, size_t i0)
{
    const hv_slicer *s = w->s;
    double h = w->h, p[2];
    uint32_t f0 = w->cross[i0];
    unsigned b0 = below_mask(s, f0, h);
    int exit0 = up_edge(b0), entry0 = other_crossed(b0, exit0);
    w->visited[i0] = 1;
    if (w->nchains + 1 > w->cap_chains &&
        hv_grow((void **)&w->chains, &w->cap_chains, w->nchains + 1, sizeof *w->chains) != HV_OK)
        return HV_ERR_NOMEM;
    chain *c = &w->chains[w->nchains];
    memset(c, 0, sizeof *c);
    c->next = -1;
    c->tail = (int)w->nchains;
    c->body = s->nbodies > 1 ? hv_slicer_body_of(s, f0) : 0;
    c->off = w->nfw;
    c->boff = w->nbw;
    ++w->nchains;

    uint32_t f = f0;
    int ex = exit0;
    int open = 0;
    double prev[2], vote = 0;
    edge_point(s, f0, entry0, h, prev); /* where the loop enters the start facet */
    for (;;) {
        edge_point(s, f, ex, h, p);
        vote += facet_vote(s, f, prev, p);
        prev[0] = p[0];
        prev[1] = p[1];
        if (push_point(&w->fw, &w->nfw, &w->cap_fw, p) != HV_OK) return HV_ERR_NOMEM;
        int32_t g = s->arc[3 * (size_t)f + (size_t)(ex - 1)];
        if (g < 0) {
            open = 1;
            break;
        }
        int wg = hv_wdg_back(s, f, ex);
        if ((uint32_t)g == f0 && wg == entry0) break; /* back at the start: closed */
        long j = lookup(w, (uint32_t)g);
        /* arcs are an involution, so only the start can be reached twice; anything else means
         * an inconsistent mesh and ends the chain as open */
        if (j < 0 || w->visited[j]) {
            open = 1;
            break;
        }
        unsigned bg = below_mask(s, (uint32_t)g, h);
        int nx = crossed(bg, wg) ? other_crossed(bg, wg) : 0;
        if (!nx) {
            open = 1;
            break;
        }
        w->visited[j] = 1;
        f = (uint32_t)g;
        ex = nx;
    }
    c = &w->chains[w->nchains - 1];
    c->n = w->nfw - c->off;
    if (!open) {
        c->closed = 1;
        c->vote = vote;
        return HV_OK;
    }
    /* open: trace backwards from the start's entry edge to the other boundary; in loop order
     * the segment of each facet runs from the point found next to the one found before */
    f = f0;
    int en = entry0;
    for (int k = 0;; ++k) {
        edge_point(s, f, en, h, p);
        if (k > 0) vote += facet_vote(s, f, p, prev);
        prev[0] = p[0];
        prev[1] = p[1];
        if (push_point(&w->bw, &w->nbw, &w->cap_bw, p) != HV_OK) return HV_ERR_NOMEM;
        int32_t g = s->arc[3 * (size_t)f + (size_t)(en - 1)];
        if (g < 0) break;
        int wg = hv_wdg_back(s, f, en);
        long j = lookup(w, (uint32_t)g);
        if (j < 0 || w->visited[j]) break;
        unsigned bg = below_mask(s, (uint32_t)g, h);
        int nx = crossed(bg, wg) ? other_crossed(bg, wg) : 0;
        if (!nx) break;
        w->visited[j] = 1;
        f = (uint32_t)g;
        en = nx;
    }
    c = &w->chains[w->nchains - 1];
    c->bn = w->nbw - c->boff;
    c->vote = vote;
    return HV_OK;
}

static inline void chain_start(const work *w, const chain *c, double p[2])
{
    const double *q = c->bn ? w->bw + 2 * (c->boff + c->bn - 1) : w->fw + 2 * c->off;
    p[0] = q[0];
    p[1] = q[1];
}

static inline void chain_end(const work *w, const chain *c, double p[2])
{
    const double *q = w->fw + 2 * (c->off + c->n - 1);
    p[0] = q[0];
    p[1] = q[1];
}

/* Gap rule (see slice.h): in chain order, join the end of each open list to the nearest
 * start of an open list (itself included) within close_gap, until none is near enough. The
 * open starts are indexed in a grid of close_gap cells (sorted by cell), so a mesh whose
 * every edge is open (an unwelded triangle soup) costs O(m log m), not O(m^2). */
typedef struct gap_key {
    int64_t cx, cy;
    size_t chain;
} gap_key;

static int cmp_gap_key(const void *a, const void *b)
{
    const gap_key *x = a, *y = b;
    if (x->cx != y->cx) return x->cx < y->cx ? -1 : 1;
    if (x->cy != y->cy) return x->cy < y->cy ? -1 : 1;
    return x->chain < y->chain ? -1 : x->chain > y->chain;
}

static inline int64_t gap_cell(double v, double cell)
{
    double c = floor(v / cell);
    return c < -4e18 ? (int64_t)-4e18 : c > 4e18 ? (int64_t)4e18 : (int64_t)c;
}

static hv_status close_gaps(work *w, double gap)
{
    size_t m = 0;
    for (size_t i = 0; i < w->nchains; ++i) m += !w->chains[i].closed;
    if (m == 0) return HV_OK;
    double cell = gap > 0 ? gap : 1.0, g2 = gap * gap;
    gap_key *keys = hv_malloc_array(m, sizeof *keys);
    if (!keys) return HV_ERR_NOMEM;
    m = 0;
    for (size_t i = 0; i < w->nchains; ++i) {
        if (w->chains[i].closed) continue;
        double sp[2];
        chain_start(w, &w->chains[i], sp);
        keys[m].cx = gap_cell(sp[0], cell);
        keys[m].cy = gap_cell(sp[1], cell);
        keys[m].chain = i;
        ++m;
    }
    qsort(keys, m, sizeof *keys, cmp_gap_key);
    for (size_t i = 0; i < w->nchains; ++i) {
        chain *ci = &w->chains[i];
        if (ci->closed || ci->absorbed) continue;
        for (;;) {
            double e[2];
            chain_end(w, &w->chains[ci->tail], e);
            int64_t ex = gap_cell(e[0], cell), ey = gap_cell(e[1], cell);
            long best = -1;
            double bd = 0;
            for (int64_t dx = -1; dx <= 1; ++dx) {
                gap_key probe = {ex + dx, ey - 1, 0};
                /* first key >= (ex + dx, ey - 1) */
                size_t lo = 0, hi = m;
                while (lo < hi) {
                    size_t mid = lo + (hi - lo) / 2;
                    if (cmp_gap_key(&keys[mid], &probe) < 0) lo = mid + 1;
                    else hi = mid;
                }
                for (size_t k = lo; k < m && keys[k].cx == ex + dx && keys[k].cy <= ey + 1; ++k) {
                    const chain *cj = &w->chains[keys[k].chain];
                    if (cj->closed || cj->absorbed || cj->body != ci->body) continue; /* bodies apart */
                    double sp[2];
                    chain_start(w, cj, sp);
                    double ux = sp[0] - e[0], uy = sp[1] - e[1], d = ux * ux + uy * uy;
                    if (d <= g2 && (best < 0 || d < bd || (d == bd && (long)keys[k].chain < best))) {
                        best = (long)keys[k].chain;
                        bd = d;
                    }
                }
            }
            if (best < 0) break;
            ++ci->gaps;
            if ((size_t)best == i) {
                ci->closed = 1;
                break;
            }
            chain *cb = &w->chains[best];
            w->chains[ci->tail].next = (int)best;
            ci->tail = cb->tail;
            ci->gaps += cb->gaps;
            ci->vote += cb->vote;
            cb->absorbed = 1;
        }
    }
    free(keys);
    return HV_OK;
}

/* ---- assembly, area, nesting ------------------------------------------------------------- */

static inline int same(const double *a, const double *b) { return a[0] == b[0] && a[1] == b[1]; }

/* Copy chain list `head` into out (dedup consecutive points); returns the count. */
static size_t assemble(const work *w, int head, double *out)
{
    size_t n = 0;
    for (int k = head; k >= 0; k = w->chains[k].next) {
        const chain *c = &w->chains[k];
        for (size_t i = c->bn; i-- > 0;) {
            const double *q = w->bw + 2 * (c->boff + i);
            if (n && same(out + 2 * (n - 1), q)) continue;
            out[2 * n] = q[0];
            out[2 * n + 1] = q[1];
            ++n;
        }
        for (size_t i = 0; i < c->n; ++i) {
            const double *q = w->fw + 2 * (c->off + i);
            if (n && same(out + 2 * (n - 1), q)) continue;
            out[2 * n] = q[0];
            out[2 * n + 1] = q[1];
            ++n;
        }
    }
    return n;
}

static double loop_area(const double *xy, size_t n)
{
    double x0 = xy[0], y0 = xy[1], a = 0;
    for (size_t i = 1; i + 1 < n; ++i) {
        double ax = xy[2 * i] - x0, ay = xy[2 * i + 1] - y0;
        double bx = xy[2 * i + 2] - x0, by = xy[2 * i + 3] - y0;
        a += ax * by - bx * ay;
    }
    return 0.5 * a;
}

/* Crossing-number point in polygon with the half-open rule on y. */
static int inside(const double *xy, size_t n, double px, double py)
{
    int in = 0;
    for (size_t i = 0, j = n - 1; i < n; j = i++) {
        double yi = xy[2 * i + 1], yj = xy[2 * j + 1];
        if ((yi > py) != (yj > py)) {
            double xi = xy[2 * i], xj = xy[2 * j];
            double x = xi + (py - yi) / (yj - yi) * (xj - xi);
            if (px < x) in = !in;
        }
    }
    return in;
}

typedef struct nest_item {
    double absarea;
    size_t idx;
    double bb[4];
} nest_item;

static int cmp_nest(const void *a, const void *b)
{
    const nest_item *x = a, *y = b;
    if (x->absarea != y->absarea) return x->absarea > y->absarea ? -1 : 1;
    return x->idx < y->idx ? -1 : x->idx > y->idx;
}

/* Parent = smallest loop of the same body containing the loop (by vote of up to 5 of its
 * vertices). The facets decide outer (CCW) or hole (CW): votes[i] > 0 keeps loop i's direction,
 * < 0 reverses it (negated when the loop's body is inside out); depth parity decides a loop
 * without a vote. */
static hv_status nest(hv_slice *sl, size_t nclosed, const double *votes, const hv_slicer *s)
{
    if (nclosed == 0) return HV_OK;
    nest_item *it = hv_malloc_array(nclosed, sizeof *it);
    if (!it) return HV_ERR_NOMEM;
    for (size_t i = 0; i < nclosed; ++i) {
        const hv_slice_loop *L = &sl->loops[i];
        it[i].absarea = fabs(L->area);
        it[i].idx = i;
        double *bb = it[i].bb;
        bb[0] = bb[2] = L->xy[0];
        bb[1] = bb[3] = L->xy[1];
        for (size_t k = 1; k < L->count; ++k) {
            double x = L->xy[2 * k], y = L->xy[2 * k + 1];
            bb[0] = HV_MIN(bb[0], x);
            bb[2] = HV_MAX(bb[2], x);
            bb[1] = HV_MIN(bb[1], y);
            bb[3] = HV_MAX(bb[3], y);
        }
    }
    qsort(it, nclosed, sizeof *it, cmp_nest);
    for (size_t r = 0; r < nclosed; ++r) {
        hv_slice_loop *L = &sl->loops[it[r].idx];
        const double *bb = it[r].bb;
        L->parent = -1;
        L->depth = 0;
        /* candidates are larger loops; the smallest containing one is the parent */
        for (size_t q = r; q-- > 0;) {
            const double *pb = it[q].bb;
            if (!(it[q].absarea > it[r].absarea) || pb[0] > bb[0] || pb[1] > bb[1] ||
                pb[2] < bb[2] || pb[3] < bb[3])
                continue;
            const hv_slice_loop *P = &sl->loops[it[q].idx];
            if (P->body != L->body) continue;
            size_t samples = HV_MIN(L->count, (size_t)5), ins = 0;
            for (size_t k = 0; k < samples; ++k) {
                size_t v = k * L->count / samples;
                ins += (size_t)inside(P->xy, P->count, L->xy[2 * v], L->xy[2 * v + 1]);
            }
            if (2 * ins > samples) {
                L->parent = (int)it[q].idx;
                L->depth = P->depth + 1;
                break;
            }
        }
    }
    free(it);
    for (size_t i = 0; i < nclosed; ++i) {
        hv_slice_loop *L = &sl->loops[i];
        double v = s && s->body_inverted[L->body] ? -votes[i] : votes[i];
        int traced = L->area > 0 ? 1 : -1;
        int want = v > 0 ? traced : v < 0 ? -traced : L->depth % 2 == 0 ? 1 : -1;
        if ((L->area > 0 ? 1 : -1) != want) {
            double *xy = (double *)L->xy;
            for (size_t a = 0, b = L->count - 1; a < b; ++a, --b) {
                double tx = xy[2 * a], ty = xy[2 * a + 1];
                xy[2 * a] = xy[2 * b];
                xy[2 * a + 1] = xy[2 * b + 1];
                xy[2 * b] = tx;
                xy[2 * b + 1] = ty;
            }
            L->area = -L->area;
        }
        L->orientation = want;
        if (want > 0) ++sl->stats.outers;
        else ++sl->stats.holes;
        sl->stats.area += L->area;
    }
    return HV_OK;
}

static hv_status build_slice(work *w, double gap, hv_slice **out)
{
    if (close_gaps(w, gap) != HV_OK) return HV_ERR_NOMEM;
    hv_slice *sl = hv_calloc(1, sizeof *sl);
    if (!sl) return HV_ERR_NOMEM;
    sl->stats.z = w->h;
    sl->stats.facets = w->ncross;
    size_t total = w->nfw + w->nbw;
    sl->xy = hv_malloc_array(2 * HV_MAX(total, (size_t)1), sizeof *sl->xy);
    sl->loops = hv_malloc_array(HV_MAX(w->nchains, (size_t)1), sizeof *sl->loops);
    double *votes = hv_malloc_array(HV_MAX(w->nchains, (size_t)1), sizeof *votes);
    if (!sl->xy || !sl->loops || !votes) {
        free(votes);
        hv_slice_destroy(sl);
        return HV_ERR_NOMEM;
    }
    size_t used = 0, nl = 0;
    /* closed loops first, then open polylines, each in chain order */
    for (int pass = 0; pass < 2; ++pass) {
        for (size_t i = 0; i < w->nchains; ++i) {
            const chain *c = &w->chains[i];
            if (c->absorbed || c->closed != (pass == 0)) continue;
            double *xy = sl->xy + 2 * used;
            size_t n = assemble(w, (int)i, xy);
            if (pass == 0)
                while (n > 1 && same(xy, xy + 2 * (n - 1))) --n;
            double area = pass == 0 && n >= 3 ? loop_area(xy, n) : 0.0;
            if (n < (pass == 0 ? 3u : 2u) || (pass == 0 && area == 0)) {
                ++sl->stats.dropped;
                continue;
            }
            if (pass == 0) votes[nl] = c->vote;
            hv_slice_loop *L = &sl->loops[nl++];
            L->xy = xy;
            L->count = n;
            L->closed = pass == 0;
            L->orientation = 0;
            L->parent = -1;
            L->depth = pass == 0 ? 0 : -1;
            L->gaps = c->gaps;
            L->area = area;
            L->body = c->body;
            used += n;
            sl->stats.points += n;
            if (pass == 0) {
                ++sl->stats.loops;
                sl->stats.gaps_closed += (size_t)c->gaps;
            } else {
                ++sl->stats.open;
            }
        }
    }
    sl->nloops = nl;
    hv_status st = nest(sl, sl->stats.loops, votes, w->s);
    free(votes);
    if (st != HV_OK) {
        hv_slice_destroy(sl);
        return HV_ERR_NOMEM;
    }
    *out = sl;
    return HV_OK;
}

hv_status hv_slice_from_loops(double z, const double *const *xy, const size_t *count, size_t n, hv_slice **out)
{
    *out = NULL;
    if (!isfinite(z)) return hv_error_set(HV_ERR_INVALID, "slice from loops: z = %g is not finite", z);
    size_t total = 0;
    for (size_t i = 0; i < n; ++i) {
        for (size_t k = 0; k < 2 * count[i]; ++k)
            if (!isfinite(xy[i][k]))
                return hv_error_set(HV_ERR_INVALID, "slice from loops: loop %zu point %zu is not finite", i, k / 2);
        total += count[i];
    }
    hv_slice *sl = hv_calloc(1, sizeof *sl);
    if (!sl) return HV_ERR_NOMEM;
    sl->stats.z = z;
    sl->xy = hv_malloc_array(2 * HV_MAX(total, (size_t)1), sizeof *sl->xy);
    sl->loops = hv_malloc_array(HV_MAX(n, (size_t)1), sizeof *sl->loops);
    double *votes = hv_malloc_array(HV_MAX(n, (size_t)1), sizeof *votes);
    if (!sl->xy || !sl->loops || !votes) {
        free(votes);
        hv_slice_destroy(sl);
        return HV_ERR_NOMEM;
    }
    size_t used = 0, nl = 0;
    for (size_t i = 0; i < n; ++i) {
        double *dst = sl->xy + 2 * used;
        size_t m = 0;
        for (size_t k = 0; k < count[i]; ++k) {
            if (m && same(dst + 2 * (m - 1), xy[i] + 2 * k)) continue;
            dst[2 * m] = xy[i][2 * k];
            dst[2 * m + 1] = xy[i][2 * k + 1];
            ++m;
        }
        while (m > 1 && same(dst, dst + 2 * (m - 1))) --m;
        double area = m >= 3 ? loop_area(dst, m) : 0.0;
        if (m < 3 || area == 0) {
            ++sl->stats.dropped;
            continue;
        }
        votes[nl] = 1.0; /* keep the direction given */
        hv_slice_loop *L = &sl->loops[nl++];
        *L = (hv_slice_loop){dst, m, 1, 0, -1, 0, 0, area, 0};
        used += m;
        sl->stats.points += m;
        ++sl->stats.loops;
    }
    sl->nloops = nl;
    hv_status st = nest(sl, nl, votes, NULL);
    free(votes);
    if (st != HV_OK) {
        hv_slice_destroy(sl);
        return st;
    }
    *out = sl;
    return HV_OK;
}

static hv_status slice_plane(const hv_slicer *s, double h, double gap, work *w, hv_slice **out)
{
    memset(w, 0, sizeof *w);
    w->s = s;
    w->h = h;
    hv_status st = hv_slicer_crossing(s, h, &w->cross, &w->cap_cross, &w->ncross);
    if (st != HV_OK) return st;
    size_t k = w->ncross;
    if (k) {
        w->tmp = hv_malloc_array(k, sizeof *w->tmp);
        if (!w->tmp) return HV_ERR_NOMEM;
        sort_u32(w->cross, w->tmp, k);
    }
    /* facet -> slot hash, load <= 1/2 */
    w->hbits = 4;
    while (((size_t)1 << w->hbits) < 2 * k) ++w->hbits;
    size_t hs = (size_t)1 << w->hbits;
    w->hmask = hs - 1;
    w->hkey = hv_malloc_array(hs, sizeof *w->hkey);
    w->hval = hv_malloc_array(hs, sizeof *w->hval);
    w->visited = hv_calloc(HV_MAX(k, (size_t)1), 1);
    if (!w->hkey || !w->hval || !w->visited) return HV_ERR_NOMEM;
    memset(w->hkey, 0xff, hs * sizeof *w->hkey);
    for (size_t i = 0; i < k; ++i) {
        size_t j = hslot(w, w->cross[i]);
        while (w->hkey[j] != UINT32_MAX) j = (j + 1) & w->hmask;
        w->hkey[j] = w->cross[i];
        w->hval[j] = (uint32_t)i;
    }
    /* Wu's traversal: start at each unvisited crossing facet in facet order */
    for (size_t i = 0; i < k; ++i)
        if (!w->visited[i] && (st = trace(w, i)) != HV_OK) return st;
    return build_slice(w, gap, out);
}

static hv_status check_options(const hv_slice_options *o, double *gap)
{
    *gap = o ? o->close_gap : HV_SLICE_DEFAULT_CLOSE_GAP;
    if (!(*gap >= 0) || !isfinite(*gap))
        return hv_error_set(HV_ERR_INVALID, "slice: close_gap %g must be finite and >= 0", *gap);
    return HV_OK;
}

hv_status hv_slicer_slice(const hv_slicer *s, double h, const hv_slice_options *o,
                          hv_slice **out)
{
    if (!out) return hv_error_set(HV_ERR_INVALID, "hv_slicer_slice: out is NULL");
    *out = NULL;
    if (!s) return hv_error_set(HV_ERR_INVALID, "hv_slicer_slice: slicer is NULL");
    if (!isfinite(h)) return hv_error_set(HV_ERR_INVALID, "slice: height %g is not finite", h);
    double gap;
    hv_status st = check_options(o, &gap);
    if (st != HV_OK) return st;
    work w;
    st = slice_plane(s, h, gap, &w, out);
    work_free(&w);
    if (st == HV_ERR_NOMEM) return hv_error_set(st, "slice at z = %g: out of memory", h);
    return st;
}

/* ---- every layer of a plan ------------------------------------------------------------------ */

typedef struct batch_ctx {
    const hv_slicer *s;
    const hv_layer *layers;
    double gap;
    hv_slice **out;
} batch_ctx;

static hv_status batch_range(void *c, size_t b, size_t e, int t)
{
    (void)t;
    batch_ctx *x = c;
    for (size_t i = b; i < e; ++i) {
        work w;
        hv_status st = slice_plane(x->s, x->layers[i].z, x->gap, &w, &x->out[i]);
        work_free(&w);
        if (st != HV_OK)
            return hv_error_set(st, "slice at z = %g: out of memory", x->layers[i].z);
    }
    return HV_OK;
}

hv_status hv_slicer_slice_plan(const hv_slicer *s, const hv_layer_plan *plan,
                               const hv_slice_options *o, hv_slice_sink_fn sink, void *user,
                               const hv_progress *progress)
{
    if (!s || !plan || !sink)
        return hv_error_set(HV_ERR_INVALID, "hv_slicer_slice_plan: slicer, plan and sink are required");
    double gap;
    hv_status st = check_options(o, &gap);
    if (st != HV_OK) return st;
    size_t n = hv_layer_plan_count(plan);
    const hv_layer *layers = hv_layer_plan_layers(plan);
    /* a window of layers is sliced in parallel, then handed over in order and freed */
    size_t window = HV_MAX((size_t)16, 8 * (size_t)hv_threads());
    hv_slice **buf = hv_calloc(HV_MIN(window, HV_MAX(n, (size_t)1)), sizeof *buf);
    if (!buf) return HV_ERR_NOMEM;
    st = hv_progress_report(progress, "contours", 0.0);
    for (size_t w0 = 0; st == HV_OK && w0 < n; w0 += window) {
        size_t cnt = HV_MIN(window, n - w0);
        batch_ctx x = {s, layers + w0, gap, buf};
        st = hv_parallel_for(cnt, 1, batch_range, &x, NULL, "contours");
        for (size_t i = 0; i < cnt; ++i) {
            if (st == HV_OK) st = sink(user, w0 + i, &layers[w0 + i], &buf[i]);
            hv_slice_destroy(buf[i]);
            buf[i] = NULL;
        }
        if (st == HV_OK) st = hv_progress_report(progress, "contours", (double)(w0 + cnt) / (double)n);
    }
    free(buf);
    if (st == HV_OK && n == 0) st = hv_progress_report(progress, "contours", 1.0);
    return st;
}
