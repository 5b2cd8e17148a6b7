/* slicing/slice_internal.h - the slicer object (Wu 2.4.1 weighted directed graph plus the
 * z-sorted facet index) shared by the graph builder, the contour tracer and the planners. */
#ifndef HOVOX_SLICE_INTERNAL_H
#define HOVOX_SLICE_INTERNAL_H

#include "hovox/slice.h"

/* Facets are grouped by z-extent class (extent in (base*2^(c-1), base*2^c]); within a class
 * they are sorted by lowest z, so the facets crossing z = h in class c are found by two
 * binary searches: zmin in [h - ext[c], h). */
#define HV_SLICE_CLASSES 48

struct hv_slicer {
    size_t nf, nv;
    double *xyz;       /* 3 per vertex */
    uint32_t *tri;     /* 3 per facet */
    int32_t *arc;      /* 3 per facet, slot w-1 for Wu weight w: neighbour facet or -1 */
    uint8_t *back;     /* per facet: 2 bits per slot (bits 2(w-1)..): the neighbour's weight */
    /* z index */
    uint32_t *order;   /* facets by (class, zmin, index) */
    double *szmin, *szmax; /* zmin / zmax in `order` */
    size_t class_start[HV_SLICE_CLASSES + 1];
    double class_ext[HV_SLICE_CLASSES];
    hv_slicer_info info;
    float *nxy;   /* 2 per facet: the unit horizontal part of the outward normal (0, 0 when
                   * the facet is horizontal or degenerate), for the orientation vote */
    int inverted; /* the mesh's signed volume is negative (inside out): loop votes flip */
    /* bodies (hv_mesh_body_*): facets [body_first[b], body_first[b + 1]) are body b, sliced
     * from its own facets (arcs never leave a body: each body is welded alone) */
    size_t nbodies;         /* >= 1 */
    size_t *body_first;     /* nbodies + 1 */
    uint8_t *body_inverted; /* per body: its signed volume is negative */
};

/* The body of facet f. */
static inline int hv_slicer_body_of(const struct hv_slicer *s, uint32_t f)
{
    size_t lo = 0, hi = s->nbodies; /* body_first[lo] <= f < body_first[hi] */
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2;
        if (s->body_first[mid] <= f) lo = mid;
        else hi = mid;
    }
    return (int)lo;
}

/* Wu weight of the edge between local vertices a and b (a != b) is a + b, so the edge of
 * weight w joins the two vertices other than 3 - w. The neighbour's weight of arc (f, w): */
static inline int hv_wdg_back(const struct hv_slicer *s, size_t f, int w)
{
    return (s->back[f] >> (2 * (w - 1))) & 3;
}

/* The facets crossing z = h (zmin < h <= zmax), appended to *buf (capacity *cap, grown with
 * hv_grow) in no particular order; returns their count in *n. Errors: HV_ERR_NOMEM. */
hv_status hv_slicer_crossing(const struct hv_slicer *s, double h, uint32_t **buf, size_t *cap,
                             size_t *n);

/* Index range [*lo, *hi) in `order` of class c whose zmin lies in [a, b). */
void hv_slicer_class_range(const struct hv_slicer *s, int c, double a, double b, size_t *lo,
                           size_t *hi);

#endif
