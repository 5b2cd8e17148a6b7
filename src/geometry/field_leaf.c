/* src/geometry/field_leaf.c - the FIELD_ISO kind of leaf (hovox/solid.h; the scanned-volume
 * module's, DESIGN-ROUND "Geometry truth"): the iso-surface of a scanned field, its data packed by
 * src/io/scan/pack.c and placed by the leaf's transform (the scan's affine). Outlines at height z
 * by marching squares (Lorensen-Cline's 2-D case) on the trilinearly interpolated field
 * (src/io/scan/level.c), on a square grid of half the smallest sample spacing over the leaf's box;
 * crossings placed by linear interpolation along the grid edges; saddles decided by the cell
 * centre's value; segments oriented with the inside on their left, so outers run counter-clockwise
 * and holes clockwise, and linked into loops through the edges they share. Inside: g >= 0. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "geometry_internal.h"
#include "io/scan/scan_internal.h"

typedef struct field_leaf {
    hv_scan *scan;
    int32_t *labels;
    hv_scan_level lv;
    double lo[3], hi[3], h; /* box, grid pitch */
} field_leaf;

static void field_close(void *state)
{
    field_leaf *f = state;
    if (!f) return;
    hv_scan_level_free(&f->lv);
    hv_scan_destroy(f->scan);
    free(f->labels);
    free(f);
}

static hv_status field_open(const hv_geometry *g, size_t i, const hv_progress *progress, void **state)
{
    (void)progress;
    *state = NULL;
    const hv_geometry_leaf *info = hv_geometry_leaf_at(g, i);
    field_leaf *f = hv_calloc(1, sizeof *f);
    if (!f) return HV_ERR_NOMEM;
    hv_scan_shape shape;
    hv_status st = hv_scan_unpack(hv_geometry_leaf_data(g, i), info->size, info->name, info->transform, &f->scan, &shape,
                                  &f->labels);
    if (st == HV_OK) st = hv_scan_level_init(f->scan, &shape, &f->lv);
    if (st != HV_OK) {
        field_close(f);
        return st;
    }
    double sp[3], lo[3], hi[3];
    char axes[4];
    hv_scan_geometry(f->scan, sp, axes, lo, hi);
    f->h = fmin(sp[0], fmin(sp[1], sp[2])) / 2;
    st = hv_scan_inside_box(&f->lv, f->lo, f->hi);
    if (st != HV_OK) {
        field_close(f);
        return st;
    }
    *state = f;
    return HV_OK;
}

static void field_bbox(const void *state, double min[3], double max[3])
{
    const field_leaf *f = state;
    memcpy(min, f->lo, sizeof f->lo);
    memcpy(max, f->hi, sizeof f->hi);
}

static int field_inside(const void *state, const double p[3])
{
    const field_leaf *f = state;
    return hv_scan_level_at(&f->lv, p) >= 0;
}

typedef struct ms_loops {
    double **xy;
    size_t *count, n, cap;
} ms_loops;

static hv_status field_slice(const void *state, double z, const hv_slice_options *o, hv_slice **out)
{
    (void)o;
    const field_leaf *f = state;
    *out = NULL;
    if (!(z >= f->lo[2] && z <= f->hi[2]) || f->lo[0] >= f->hi[0]) return hv_slice_from_loops(z, NULL, NULL, 0, out);
    double h = f->h, x0 = f->lo[0] - h, y0 = f->lo[1] - h;
    size_t W = (size_t)ceil((f->hi[0] - f->lo[0]) / h) + 3, H = (size_t)ceil((f->hi[1] - f->lo[1]) / h) + 3;
    if ((double)W * (double)H > 4e8) return hv_error_set(HV_ERR_LIMIT, "field leaf: a %zu x %zu grid at z = %g", W, H, z);
    double *g = hv_malloc_array(W * H, sizeof *g);
    /* the crossing on each edge: horizontal edge (i,j)-(i+1,j) id 2 (j W + i), vertical (i,j)-(i,j+1) +1 */
    size_t ne = 2 * W * H;
    double *px = hv_malloc_array(ne, 2 * sizeof *px);
    size_t *next = hv_malloc_array(ne, sizeof *next);
    hv_status st = g && px && next ? HV_OK : HV_ERR_NOMEM;
    ms_loops L = {0};
    if (st != HV_OK) goto done;
    for (size_t j = 0; j < H; ++j)
        for (size_t i = 0; i < W; ++i) {
            double p[3] = {x0 + (double)i * h, y0 + (double)j * h, z};
            /* the ring around the grid is outside, so every loop closes */
            g[j * W + i] = i == 0 || j == 0 || i == W - 1 || j == H - 1 ? -1.0 : hv_scan_level_at(&f->lv, p);
            if (isinf(g[j * W + i])) g[j * W + i] = -1e30;
        }
    for (size_t e = 0; e < ne; ++e) next[e] = SIZE_MAX;
#define IN(i, j) (g[(j) * W + (i)] >= 0)
    for (size_t j = 0; j + 1 < H; ++j)
        for (size_t i = 0; i + 1 < W; ++i) {
            /* corners counter-clockwise: (i,j) (i+1,j) (i+1,j+1) (i,j+1); edges between them */
            size_t ci[4] = {i, i + 1, i + 1, i}, cj[4] = {j, j, j + 1, j + 1};
            size_t eid[4] = {2 * (j * W + i), 2 * (j * W + i + 1) + 1, 2 * ((j + 1) * W + i), 2 * (j * W + i) + 1};
            int in[4], any = 0, all = 1;
            for (int c = 0; c < 4; ++c) {
                in[c] = IN(ci[c], cj[c]);
                any |= in[c];
                all &= in[c];
            }
            if (!any || all) continue;
            int outx[2], inx[2], no = 0, ni = 0; /* crossings in->out and out->in, by edge number */
            for (int c = 0; c < 4; ++c) {
                int d = (c + 1) & 3;
                if (in[c] == in[d]) continue;
                double ga = g[cj[c] * W + ci[c]], gb = g[cj[d] * W + ci[d]];
                double t = ga / (ga - gb);
                size_t e = eid[c];
                px[2 * e] = x0 + ((double)ci[c] + t * ((double)ci[d] - (double)ci[c])) * h;
                px[2 * e + 1] = y0 + ((double)cj[c] + t * ((double)cj[d] - (double)cj[c])) * h;
                if (in[c]) outx[no++] = c;
                else inx[ni++] = c;
            }
            if (no == 1) {
                next[eid[outx[0]]] = eid[inx[0]];
                continue;
            }
            /* a saddle: the centre decides whether the insides join */
            double centre = 0.25 * (g[j * W + i] + g[j * W + i + 1] + g[(j + 1) * W + i] + g[(j + 1) * W + i + 1]);
            int joined = centre >= 0;
            for (int k = 0; k < 2; ++k) {
                int c = outx[k], best = -1;
                for (int s = 1; s <= 3 && best < 0; ++s) {
                    int cand = joined ? (c + s) & 3 : (c - s + 4) & 3;
                    if (cand == inx[0] || cand == inx[1]) best = cand;
                }
                next[eid[c]] = eid[best];
            }
        }
#undef IN
    /* link: every crossing edge starts one segment and ends one */
    for (size_t e = 0; e < ne && st == HV_OK; ++e) {
        if (next[e] == SIZE_MAX) continue;
        size_t cap = 64, cnt = 0;
        double *xy = hv_malloc_array(cap, 2 * sizeof *xy);
        if (!xy) {
            st = HV_ERR_NOMEM;
            break;
        }
        size_t at = e;
        while (at != SIZE_MAX && next[at] != SIZE_MAX) {
            if (cnt == cap && (st = hv_grow((void **)&xy, &cap, cnt + 1, 2 * sizeof *xy)) != HV_OK) break;
            xy[2 * cnt] = px[2 * at];
            xy[2 * cnt + 1] = px[2 * at + 1];
            ++cnt;
            size_t nx = next[at];
            next[at] = SIZE_MAX;
            at = nx;
        }
        if (st == HV_OK) st = hv_grow((void **)&L.xy, &L.cap, L.n + 1, sizeof *L.xy);
        if (st == HV_OK) {
            size_t cc = L.cap;
            size_t *nc = realloc(L.count, cc * sizeof *nc);
            if (!nc) st = hv_error_set(HV_ERR_NOMEM, "out of memory");
            else L.count = nc;
        }
        if (st != HV_OK) {
            free(xy);
            break;
        }
        L.xy[L.n] = xy;
        L.count[L.n++] = cnt;
    }
    if (st == HV_OK) st = hv_slice_from_loops(z, (const double *const *)L.xy, L.count, L.n, out);
done:
    for (size_t k = 0; k < L.n; ++k) free(L.xy[k]);
    free(L.xy);
    free(L.count);
    free(g);
    free(px);
    free(next);
    return st;
}

const hv_leaf_ops hv_leaf_field_ops = {HV_LEAF_FIELD_ISO, field_open, field_close, field_bbox, field_slice, field_inside};
