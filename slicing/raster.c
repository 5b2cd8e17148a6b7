/* slicing/raster.c - scan conversion of a slice's contour loops at printer resolution (the
 * geometric constraint of Wu 2.4.2): centre sampling with the nonzero or even-odd rule, and
 * Wu's distance threshold that keeps pixels within d of the contour as object. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/layers.h"

typedef struct crossing {
    double x;
    int dir;
    int body; /* the loop's body: even-odd fills are united body by body */
} crossing;

static int cmp_crossing(const void *a, const void *b)
{
    const crossing *p = a, *q = b;
    if (p->x < q->x) return -1;
    if (p->x > q->x) return 1;
    return p->dir - q->dir;
}

static double row_y(const hv_raster_grid *g, int r) { return g->origin[1] + ((double)r + 0.5) * g->pixel[1]; }

/* Rows whose centre y lies in [ylo, yhi): a conservative guess tightened by the predicate. */
static void row_range(const hv_raster_grid *g, double ylo, double yhi, int *r0, int *r1)
{
    double a = (ylo - g->origin[1]) / g->pixel[1] - 0.5, b = (yhi - g->origin[1]) / g->pixel[1] - 0.5;
    double lo = floor(HV_MIN(a, b)) - 1, hi = ceil(HV_MAX(a, b)) + 1;
    lo = HV_CLAMP(lo, 0.0, (double)g->height);
    hi = HV_CLAMP(hi, -1.0, (double)g->height - 1);
    int s = (int)lo, e = (int)hi;
    while (s <= e && !(row_y(g, s) >= ylo && row_y(g, s) < yhi)) ++s;
    while (e >= s && !(row_y(g, e) >= ylo && row_y(g, e) < yhi)) --e;
    *r0 = s;
    *r1 = e;
}

/* Walk the non-horizontal edges of the closed loops over the rows whose centre they cross.
 * Without `cx`: count them per row (into at[r + 1]). With it: store each crossing, with the
 * edge's direction for the winding number, at cx[at[r]++]. */
static void edge_pass(const hv_slice *slice, const hv_raster_grid *g, size_t *at, crossing *cx)
{
    size_t nl = hv_slice_loop_count(slice);
    const hv_slice_loop *loops = hv_slice_loops(slice);
    for (size_t l = 0; l < nl; ++l) {
        const hv_slice_loop *L = &loops[l];
        if (!L->closed) continue;
        for (size_t i = 0; i < L->count; ++i) {
            const double *p = L->xy + 2 * i, *q = L->xy + 2 * ((i + 1) % L->count);
            if (p[1] == q[1]) continue;
            int r0, r1;
            row_range(g, HV_MIN(p[1], q[1]), HV_MAX(p[1], q[1]), &r0, &r1);
            if (!cx) {
                for (int r = r0; r <= r1; ++r) at[r + 1]++;
                continue;
            }
            int dir = q[1] > p[1] ? 1 : -1;
            double slope = (q[0] - p[0]) / (q[1] - p[1]);
            for (int r = r0; r <= r1; ++r) {
                crossing *c = &cx[at[r]++];
                c->x = p[0] + (row_y(g, r) - p[1]) * slope;
                c->dir = dir;
                c->body = L->body;
            }
        }
    }
}

/* Columns whose centre x lies in [xa, xb). */
static void fill_span(const hv_raster_grid *g, uint8_t *row, double xa, double xb)
{
    double a = ceil((xa - g->origin[0]) / g->pixel[0] - 0.5);
    double b = ceil((xb - g->origin[0]) / g->pixel[0] - 0.5) - 1;
    if (b < 0 || a > (double)g->width - 1 || b < a) return;
    int c0 = (int)HV_MAX(a, 0.0), c1 = (int)HV_MIN(b, (double)g->width - 1);
    if (c1 >= c0) memset(row + c0, 1, (size_t)(c1 - c0 + 1));
}

static double seg_dist2(double px, double py, const double *p, const double *q)
{
    double dx = q[0] - p[0], dy = q[1] - p[1], ex = px - p[0], ey = py - p[1];
    double l2 = dx * dx + dy * dy, t = l2 > 0 ? (ex * dx + ey * dy) / l2 : 0;
    t = HV_CLAMP(t, 0.0, 1.0);
    double rx = ex - t * dx, ry = ey - t * dy;
    return rx * rx + ry * ry;
}

static void dilate_edge(const hv_raster_grid *g, uint8_t *mask, size_t stride, const double *p,
                        const double *q, double t)
{
    double xlo = HV_MIN(p[0], q[0]) - t, xhi = HV_MAX(p[0], q[0]) + t;
    double ylo = HV_MIN(p[1], q[1]) - t, yhi = HV_MAX(p[1], q[1]) + t;
    double c0 = floor((xlo - g->origin[0]) / g->pixel[0] - 0.5), c1 = ceil((xhi - g->origin[0]) / g->pixel[0] - 0.5);
    double a = (ylo - g->origin[1]) / g->pixel[1] - 0.5, b = (yhi - g->origin[1]) / g->pixel[1] - 0.5;
    double r0 = floor(HV_MIN(a, b)), r1 = ceil(HV_MAX(a, b));
    c0 = HV_MAX(c0, 0.0);
    c1 = HV_MIN(c1, (double)g->width - 1);
    r0 = HV_MAX(r0, 0.0);
    r1 = HV_MIN(r1, (double)g->height - 1);
    double t2 = t * t;
    for (int r = (int)r0; r <= (int)r1; ++r) {
        uint8_t *row = mask + (size_t)r * stride;
        double yc = row_y(g, r);
        for (int c = (int)c0; c <= (int)c1; ++c) {
            if (row[c]) continue;
            double xc = g->origin[0] + ((double)c + 0.5) * g->pixel[0];
            if (seg_dist2(xc, yc, p, q) <= t2) row[c] = 1;
        }
    }
}

hv_status hv_slice_rasterize(const hv_slice *slice, const hv_raster_grid *g, hv_fill_rule rule,
                             double threshold, uint8_t *mask, size_t stride)
{
    if (!slice || !g || !mask) return hv_error_set(HV_ERR_INVALID, "rasterize: NULL argument");
    if (g->width < 1 || g->height < 1 || !(g->pixel[0] > 0) || !(g->pixel[1] != 0) ||
        !isfinite(g->pixel[0]) || !isfinite(g->pixel[1]) || !isfinite(g->origin[0]) ||
        !isfinite(g->origin[1]))
        return hv_error_set(HV_ERR_INVALID, "rasterize: bad grid %d x %d, pixel %g x %g", g->width,
                            g->height, g->pixel[0], g->pixel[1]);
    if (!(threshold >= 0) || !isfinite(threshold))
        return hv_error_set(HV_ERR_INVALID, "rasterize: threshold %g must be finite and >= 0", threshold);
    if (rule != HV_FILL_NONZERO && rule != HV_FILL_EVENODD)
        return hv_error_set(HV_ERR_INVALID, "rasterize: unknown fill rule %d", (int)rule);
    if (stride == 0) stride = (size_t)g->width;
    if (stride < (size_t)g->width)
        return hv_error_set(HV_ERR_INVALID, "rasterize: stride %zu below width %d", stride, g->width);
    for (int r = 0; r < g->height; ++r) memset(mask + (size_t)r * stride, 0, (size_t)g->width);

    size_t nl = hv_slice_loop_count(slice);
    const hv_slice_loop *loops = hv_slice_loops(slice);
    /* an even-odd fill of several bodies is the union of each body's own even-odd fill (a core
     * inside a shell is not a hole in it): parity per body, inside where any body is odd */
    int bodies = 0;
    for (size_t l = 0; l < nl; ++l)
        if (loops[l].closed) bodies = HV_MAX(bodies, loops[l].body + 1);
    uint8_t *parity = rule == HV_FILL_EVENODD && bodies > 1 ? hv_calloc((size_t)bodies, 1) : NULL;
    if (rule == HV_FILL_EVENODD && bodies > 1 && !parity) return HV_ERR_NOMEM;
    /* pass 1: crossings per row; pass 2: the crossings themselves */
    size_t *count = hv_calloc((size_t)g->height + 1, sizeof *count);
    if (!count) {
        free(parity);
        return HV_ERR_NOMEM;
    }
    edge_pass(slice, g, count, NULL);
    for (int r = 0; r < g->height; ++r) count[r + 1] += count[r];
    size_t total = count[g->height];
    crossing *cx = hv_malloc_array(HV_MAX(total, (size_t)1), sizeof *cx);
    size_t *fillp = hv_malloc_array((size_t)g->height + 1, sizeof *fillp);
    if (!cx || !fillp) {
        free(count);
        free(cx);
        free(fillp);
        free(parity);
        return HV_ERR_NOMEM;
    }
    memcpy(fillp, count, ((size_t)g->height + 1) * sizeof *fillp);
    edge_pass(slice, g, fillp, cx);
    free(fillp);
    for (int r = 0; r < g->height; ++r) {
        size_t a = count[r], n = count[r + 1] - a;
        if (n < 2) continue;
        crossing *c = cx + a;
        if (n == 2) {
            if (cmp_crossing(&c[0], &c[1]) > 0) {
                crossing t = c[0];
                c[0] = c[1];
                c[1] = t;
            }
        } else {
            qsort(c, n, sizeof *c, cmp_crossing);
        }
        uint8_t *row = mask + (size_t)r * stride;
        int wind = 0;
        if (parity) {
            for (size_t k = 0; k + 1 < n; ++k) {
                uint8_t *p = &parity[c[k].body];
                *p ^= 1;
                wind += *p ? 1 : -1; /* bodies inside an odd number of their loops */
                if (wind > 0 && c[k + 1].x > c[k].x) fill_span(g, row, c[k].x, c[k + 1].x);
            }
            for (size_t k = 0; k < n; ++k) parity[c[k].body] = 0;
            continue;
        }
        for (size_t k = 0; k + 1 < n; ++k) {
            wind += rule == HV_FILL_NONZERO ? c[k].dir : 1;
            int in = rule == HV_FILL_NONZERO ? wind != 0 : (wind & 1);
            if (in && c[k + 1].x > c[k].x) fill_span(g, row, c[k].x, c[k + 1].x);
        }
    }
    free(cx);
    free(count);
    free(parity);
    if (threshold > 0) {
        for (size_t l = 0; l < nl; ++l) {
            const hv_slice_loop *L = &loops[l];
            if (!L->closed) continue;
            for (size_t i = 0; i < L->count; ++i)
                dilate_edge(g, mask, stride, L->xy + 2 * i, L->xy + 2 * ((i + 1) % L->count), threshold);
        }
    }
    return HV_OK;
}
