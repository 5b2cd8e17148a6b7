/* src/viewer/outline.c - the boundary of a bitmap's set cells as closed loops of cell corners
 * (crack following: every cell side between a set and an unset cell is one directed edge, linked
 * corner to corner; at a corner shared by two diagonal cells the walk turns towards the cell it
 * came along, so diagonal neighbours stay separate loops). The viewer draws part outlines with
 * them. */
#include <stdlib.h>
#include <string.h>

#include "viewer_internal.h"

/* directions, clockwise on screen (y down): east, south, west, north */
static const int k_dx[4] = {1, 0, -1, 0};
static const int k_dy[4] = {0, 1, 0, -1};

hv_status vw_outline_trace(const uint8_t *cells, int w, int h, int32_t **xy, size_t **starts, size_t *nloops)
{
    *xy = NULL;
    *starts = NULL;
    *nloops = 0;
    if (w < 1 || h < 1) return HV_OK;
    if ((uint64_t)(w + 1) * (uint64_t)(h + 1) > (1u << 30))
        return hv_error_set(HV_ERR_LIMIT, "outline: %d x %d cells is too many", w, h);
    size_t W = (size_t)w + 1;
    uint8_t *out = hv_calloc(W * ((size_t)h + 1), 1); /* per corner: outgoing edges, bit d */
    if (!out) return HV_ERR_NOMEM;
#define SET(x, y) ((x) >= 0 && (y) >= 0 && (x) < w && (y) < h && cells[(size_t)(y) * (size_t)w + (size_t)(x)])
    size_t edges = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (!SET(x, y)) continue;
            /* the cell on the right of each edge as it is walked */
            if (!SET(x, y - 1)) out[(size_t)y * W + (size_t)x] |= 1u << 0, ++edges;           /* top, east */
            if (!SET(x + 1, y)) out[(size_t)y * W + (size_t)x + 1] |= 1u << 1, ++edges;       /* right, south */
            if (!SET(x, y + 1)) out[(size_t)(y + 1) * W + (size_t)x + 1] |= 1u << 2, ++edges; /* bottom, west */
            if (!SET(x - 1, y)) out[(size_t)(y + 1) * W + (size_t)x] |= 1u << 3, ++edges;     /* left, north */
        }
#undef SET
    /* at most one corner per edge, plus the loops' starts */
    int32_t *pts = edges ? hv_malloc_array(edges, 2 * sizeof *pts) : NULL;
    size_t *st = hv_malloc_array(edges / 4 + 2, sizeof *st);
    if ((edges && !pts) || !st) {
        free(out);
        free(pts);
        free(st);
        return HV_ERR_NOMEM;
    }
    size_t np = 0, nl = 0;
    for (size_t c0 = 0; c0 < W * ((size_t)h + 1); ++c0) {
        while (out[c0]) {
            int d0 = 0;
            while (!(out[c0] >> d0 & 1u)) ++d0;
            st[nl] = np;
            int x = (int)(c0 % W), y = (int)(c0 / W), d = d0;
            out[c0] &= (uint8_t)~(1u << d);
            for (;;) {
                x += k_dx[d];
                y += k_dy[d];
                size_t c = (size_t)y * W + (size_t)x;
                int bits = out[c] | (c == c0 ? 1 << d0 : 0);
                int nd;
                if ((bits & (bits - 1)) == 0) { /* one way on */
                    nd = 0;
                    while (!(bits >> nd & 1)) ++nd;
                } else { /* two diagonal cells meet here: turn right, round the cell we came along */
                    nd = (d + 1) & 3;
                }
                if (nd != d) {
                    pts[2 * np] = x;
                    pts[2 * np + 1] = y;
                    ++np;
                }
                if (c == c0 && nd == d0) break;
                out[c] &= (uint8_t)~(1u << nd);
                d = nd;
            }
            ++nl;
        }
    }
    st[nl] = np;
    free(out);
    *xy = pts;
    *starts = st;
    *nloops = nl;
    return HV_OK;
}
